#include "rbf_solve/rbf_solve.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "foveated_shared.h"
#include "foveation/gpu_point_set.hpp"
#include "foveation/rbf_inverse.hpp"
#include "foveation/sample_canvas.hpp"
#include "rbf_solve_comp.h"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::foveated;
using foveation::InterpolateSettings;
using foveation::RbfKernel;
using foveation::RbfWeights;

RbfSolvePass::RbfSolvePass(vk::Context& ctx) : mCtx(ctx) {
    mPipeline = std::make_unique<vk::ComputePipeline>(
        ctx, vk::ComputePipelineDesc{
                 "rbf_solve",
                 gt_spv_rbf_solve_comp,
                 {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                  VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                  VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                  VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
                 sizeof(sh::RbfSolvePush)});
}

RbfSolvePass::~RbfSolvePass() = default;

RbfWeights RbfSolvePass::add(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                             const foveation::GpuRbfInverse& inverse, rg::BufferId samples,
                             glm::vec2 gaze, const InterpolateSettings& s) const {
    points.requireIndex("rbf_solve");
    if (inverse.k() != s.k || inverse.kernel() != s.kernel || inverse.shape() != s.rbfShape) {
        throw ArgumentError("rbf_solve: the precomputed inverse was built for other settings");
    }
    if (s.k == 0 || s.k > std::min(sh::kMaxK, points.storedNeighbours() + 1)) {
        throw ArgumentError("k = " + std::to_string(s.k) + " nearest points is outside 1.." +
                            std::to_string(std::min(sh::kMaxK, points.storedNeighbours() + 1)));
    }
    if (!(s.rbfShape > 0.0f)) {
        throw ArgumentError("RBF shape c = " + std::to_string(s.rbfShape) + " is not positive");
    }
    const glm::vec2 off =
        foveation::gazeOffset(gaze, points.displayWidth(), points.displayHeight());
    const sh::RbfSolvePush push{
        glm::vec4(off, foveation::kSampleMargin, s.rbfShape),
        glm::uvec4(graph.outputWidth(), graph.outputHeight(), s.k,
                   s.kernel == RbfKernel::Gaussian ? sh::kKernelGaussian : sh::kKernelMultiquadric),
        glm::uvec4(points.count(), points.storedNeighbours(), inverse.texelsPerPoint(), 0)};
    struct Data {
        rg::BufferId samples, r, g, b;
    };
    const VkDeviceSize bytes = static_cast<VkDeviceSize>(points.count()) * s.k * sizeof(float);
    const auto& data = graph.addPass<Data>(
        "rbf_solve",
        [&](rg::PassBuilder& b, Data& d) {
            d.samples = b.read(samples, rg::Access::StorageRead);
            d.r = b.write(b.createBuffer("rbf.lambda_r", {bytes}), rg::Access::StorageWrite);
            d.g = b.write(b.createBuffer("rbf.lambda_g", {bytes}), rg::Access::StorageWrite);
            d.b = b.write(b.createBuffer("rbf.lambda_b", {bytes}), rg::Access::StorageWrite);
        },
        [ctx = &mCtx, pipeline = mPipeline.get(), pts = &points, inv = &inverse,
         push](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            vk::DescriptorWriter writer;
            writer.texelBuffer(sh::kBindingSolvePoints, pts->points())
                .storageBuffer(sh::kBindingSolveSamples, r.buffer(d.samples))
                .texelBuffer(sh::kBindingSolveNeighbours, pts->neighbours())
                .storageBuffer(sh::kBindingSolveLambdaR, r.buffer(d.r))
                .storageBuffer(sh::kBindingSolveLambdaG, r.buffer(d.g))
                .storageBuffer(sh::kBindingSolveLambdaB, r.buffer(d.b))
                .texelBuffer(sh::kBindingSolveInverse, inv->view());
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                         (push.counts.x + sh::kSolveGroupSize - 1) / sh::kSolveGroupSize, 1);
        });
    return {data.r, data.g, data.b};
}

} // namespace gt::passes
