#include "interpolate/interpolate.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "foveated_shared.h"
#include "foveation/gpu_point_set.hpp"
#include "foveation/sample_canvas.hpp"
#include "interpolate_comp.h"
#include "interpolate_sites_comp.h"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::foveated;

namespace {
const std::vector<VkDescriptorType>& interpolateBindings() {
    static const std::vector<VkDescriptorType> bindings = {
        VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
        VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
        VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,        VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
        VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,       VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
        VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
        VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,        VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
        VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
        VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,       VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
        VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER};
    return bindings;
}

const std::vector<VkDescriptorType>& sitesBindings() {
    static const std::vector<VkDescriptorType> bindings = {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
                                                           VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
    return bindings;
}

std::unique_ptr<vk::ComputePipeline> makePipeline(vk::Context& ctx,
                                                  const InterpolatePass::Variant& variant) {
    const auto& [method, table, flat, motion, exactNearest] = variant;
    return std::make_unique<vk::ComputePipeline>(
        ctx, vk::ComputePipelineDesc{"interpolate",
                                     gt_spv_interpolate_comp,
                                     interpolateBindings(),
                                     sizeof(sh::InterpolatePush),
                                     {method, table ? 1u : 0u, motion ? 1u : 0u, flat ? 1u : 0u,
                                      exactNearest ? 1u : 0u}});
}
} // namespace

InterpolatePass::InterpolatePass(vk::Context& ctx)
    : mCtx(ctx), mSites(std::make_unique<vk::ComputePipeline>(
                     ctx, vk::ComputePipelineDesc{"interpolate.sites",
                                                  gt_spv_interpolate_sites_comp,
                                                  sitesBindings(),
                                                  sizeof(sh::SitesPush),
                                                  {}})) {
    const std::pair<uint32_t, bool> variants[] = {
        {sh::kMethodNearest, false}, {sh::kMethodShepard, false}, {sh::kMethodShepard, true},
        {sh::kMethodRbf, false},     {sh::kMethodRbf, true},      {sh::kViewPoints, false},
        {sh::kViewCells, false},     {sh::kViewSpacing, false}};
    for (const auto& [method, table] : variants) {
        pipeline({method, table, false, false, false});
    }
    pipeline({sh::kMethodNearest, false, false, false, true});
}

const vk::ComputePipeline& InterpolatePass::pipeline(const Variant& variant) const {
    auto& slot = mPipelines[variant];
    if (!slot) {
        slot = makePipeline(mCtx, variant);
    }
    return *slot;
}

InterpolatePass::~InterpolatePass() = default;

namespace {
// What the settings need from the inputs: one line naming the missing or mismatched one.
void checkInputs(const foveation::GpuPointSet& points, const InterpolateSettings& s,
                 const InterpolateInputs& in) {
    if (readsNeighbourIndex(s)) {
        points.requireIndex("interpolate");
    }
    if (usesRbfSolve(s) && !in.lambdas) {
        throw ArgumentError("RBF over the neighbour lists needs the rbf_solve pass's weights");
    }
    if (s.k == 0 || s.k > points.storedNeighbours() + 1 || s.k > sh::kMaxK) {
        throw ArgumentError("k = " + std::to_string(s.k) + " nearest points is outside 1.." +
                            std::to_string(std::min(sh::kMaxK, points.storedNeighbours() + 1)));
    }
    const bool useTable = usesPixelTable(s);
    const foveation::GpuPixelKnnTable* table = useTable ? in.table : nullptr;
    if (useTable && (table == nullptr || table->k() != s.k)) {
        // The shader blends a table row as the pixel's k nearest, all of them.
        throw ArgumentError("the k-NN table must hold k = " + std::to_string(s.k) +
                            " neighbours per pixel");
    }
    const bool pixelWeights = useTable && s.method == Interpolation::Rbf;
    const foveation::GpuRbfPixelWeights* rbfWeights = pixelWeights ? in.rbfWeights : nullptr;
    if (pixelWeights && (rbfWeights == nullptr || rbfWeights->k() != s.k || table->k() != s.k ||
                         rbfWeights->shape() != s.rbfShape || rbfWeights->kernel() != s.kernel)) {
        throw ArgumentError("RBF with the k-NN table needs per-pixel weights and a table built "
                            "for the same k, kernel and shape");
    }
}
// Whether every screen pixel's nearest point lands within the sampling margin, so that it is
// one point_sample traced: a pixel centre lies within the covering radius of its nearest point,
// and with the gaze on screen the canvas holds every screen pixel (no clamping to its edge).
bool nearestIsSampled(const foveation::GpuPointSet& points, glm::vec2 gaze) {
    const glm::vec2 g(std::round(gaze.x), std::round(gaze.y));
    const bool onScreen = g.x >= 0.0f && g.y >= 0.0f &&
                          g.x <= static_cast<float>(points.displayWidth()) &&
                          g.y <= static_cast<float>(points.displayHeight());
    return onScreen && points.coveringRadius() <= foveation::kSampleMargin;
}

// The shader's method code for a setting.
uint32_t methodCode(Interpolation m) {
    switch (m) {
    case Interpolation::Nearest:
    case Interpolation::ViewMotion: // nearest neighbour, coloured by passes::MotionViewPass
        return sh::kMethodNearest;
    case Interpolation::Shepard:
        return sh::kMethodShepard;
    case Interpolation::Rbf:
        return sh::kMethodRbf;
    case Interpolation::ViewPoints:
        return sh::kViewPoints;
    case Interpolation::ViewCells:
        return sh::kViewCells;
    case Interpolation::ViewSpacing:
        return sh::kViewSpacing;
    }
    return sh::kMethodNearest;
}
// The shader's push for the settings: the canvas -> screen offset of the gaze, the method, the
// canvas and neighbour lists, the blend's parameters, the table's layout and the sites' frame.
sh::InterpolatePush interpolatePush(const rg::RenderGraph& graph,
                                    const foveation::GpuPointSet& points, glm::vec2 gaze,
                                    const InterpolateSettings& s,
                                    const foveation::GpuPixelKnnTable* table) {
    const glm::vec2 off =
        foveation::gazeOffset(gaze, points.displayWidth(), points.displayHeight());
    const uint32_t k =
        s.method == Interpolation::Shepard || s.method == Interpolation::Rbf ? s.k : 1u;
    return sh::InterpolatePush{
        glm::vec4(off, foveation::kSampleMargin, s.shepardPower),
        glm::uvec4(graph.outputWidth(), graph.outputHeight(), k, methodCode(s.method)),
        glm::uvec4(points.canvasWidth(), points.canvasHeight(), points.storedNeighbours(),
                   s.kernel == RbfKernel::Gaussian ? sh::kKernelGaussian : sh::kKernelMultiquadric),
        glm::vec4(s.rbfShape, s.displayExposure, s.edgeTolerance, s.rangeSigma),
        table ? glm::uvec4(table->texelsPerRow(), table->k(), (s.k + 3) / 4, s.siteFrame)
              : glm::uvec4(0u, 0u, 0u, s.siteFrame)};
}
} // namespace

rg::BufferId InterpolatePass::addSites(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                                       glm::vec2 offset, const InterpolateSettings& s) const {
    // Groups in two dimensions beyond the 65,535 a dimension is sure to allow.
    constexpr uint32_t kMaxGroupsX = 65535;
    const uint32_t groups = (points.count() + sh::kSitesGroup - 1) / sh::kSitesGroup;
    const uint32_t groupsX = std::max(1u, std::min(groups, kMaxGroupsX));
    const uint32_t groupsY = (groups + groupsX - 1) / groupsX;
    const sh::SitesPush push{glm::vec4(offset, s.siteJitter, 0.0f),
                             glm::uvec4(points.count(), s.siteFrame, groupsX, 0u)};
    struct Data {
        rg::BufferId sites;
    };
    const auto& data = graph.addPass<Data>(
        "interpolate.sites",
        [&](rg::PassBuilder& b, Data& d) {
            // Read as texels: on lavapipe a texel fetch per candidate cost half what a
            // storage buffer's vec4 did.
            d.sites = b.write(
                b.createBuffer("interpolate.sites", {static_cast<VkDeviceSize>(points.count()) * 16,
                                                     VK_FORMAT_R32G32B32A32_SFLOAT}),
                rg::Access::StorageWrite);
        },
        [ctx = &mCtx, pipeline = mSites.get(), pts = &points, push, groupsX,
         groupsY](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            vk::DescriptorWriter writer;
            writer.texelBuffer(sh::kBindingSitesPoints, pts->points())
                .storageBuffer(sh::kBindingSitesOut, r.buffer(d.sites));
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push), groupsX, groupsY);
        });
    return data.sites;
}

InterpolatedImage InterpolatePass::add(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                                       rg::BufferId samples, glm::vec2 gaze,
                                       const InterpolateSettings& s, const InterpolateInputs& in,
                                       std::optional<rg::BufferId> sampleMotion) const {
    checkInputs(points, s, in);
    const bool useTable = usesPixelTable(s);
    const foveation::GpuPixelKnnTable* table = useTable ? in.table : nullptr;
    const bool pixelWeights = useTable && s.method == Interpolation::Rbf;
    const foveation::GpuRbfPixelWeights* rbfWeights = pixelWeights ? in.rbfWeights : nullptr;
    const uint32_t method = methodCode(s.method);
    const sh::InterpolatePush push = interpolatePush(graph, points, gaze, s, table);
    const bool flat = table != nullptr && table->layout() == foveation::KnnLayout::Flat;
    const vk::ComputePipeline& pipe =
        pipeline({method, useTable, flat, sampleMotion.has_value(),
                  method == sh::kMethodNearest && nearestIsSampled(points, gaze)});
    // Every method but nearest neighbour weighs candidates where they sit this frame.
    const std::optional<rg::BufferId> sites =
        method == sh::kMethodNearest
            ? std::nullopt
            : std::optional(addSites(graph, points, glm::vec2(push.offset), s));
    struct Data {
        rg::BufferId samples;
        std::optional<rg::BufferId> sites;
        rg::TextureId output, support;
        std::optional<RbfWeights> weights;
        std::optional<rg::BufferId> sampleMotion;
        std::optional<rg::TextureId> motion;
    };
    const auto& data = graph.addPass<Data>(
        "interpolate",
        [&](rg::PassBuilder& b, Data& d) {
            d.samples = b.read(samples, rg::Access::StorageRead);
            if (sites) {
                d.sites = b.read(*sites, rg::Access::UniformRead);
            }
            if (usesRbfSolve(s)) {
                d.weights = RbfWeights{b.read(in.lambdas->r, rg::Access::StorageRead),
                                       b.read(in.lambdas->g, rg::Access::StorageRead),
                                       b.read(in.lambdas->b, rg::Access::StorageRead)};
            }
            d.output =
                b.write(b.createTexture("interpolate.radiance", {VK_FORMAT_R32G32B32A32_SFLOAT}),
                        rg::Access::StorageWrite);
            d.support = b.write(b.createTexture("interpolate.support", {VK_FORMAT_R32_SFLOAT}),
                                rg::Access::StorageWrite);
            if (sampleMotion) {
                d.sampleMotion = b.read(*sampleMotion, rg::Access::StorageRead);
                d.motion =
                    b.write(b.createTexture("interpolate.motion", {VK_FORMAT_R32G32B32A32_SFLOAT}),
                            rg::Access::StorageWrite);
            }
        },
        [ctx = &mCtx, pipeline = &pipe, pts = &points, knn = table, rbfWeights,
         push](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            vk::DescriptorWriter writer;
            writer.texelBuffer(sh::kBindingInterpPoints, pts->points())
                .storageBuffer(sh::kBindingInterpSamples, r.buffer(d.samples))
                .texelBuffer(sh::kBindingNearest, pts->nearest())
                .texelBuffer(sh::kBindingNeighbours, pts->neighbours())
                // A variant never reads the table or the pixel weights it was not given:
                // buffers of the same descriptor type stand in.
                .texelBuffer(sh::kBindingKnnTable, knn ? knn->slots() : pts->neighbours())
                .texelBuffer(sh::kBindingKnnTiles, knn ? knn->tiles() : pts->neighbours())
                .texelBuffer(sh::kBindingKnnCandidates, knn ? knn->candidates() : pts->neighbours())
                .texelBuffer(sh::kBindingKnnPixelRows, knn ? knn->pixelRows() : pts->neighbours())
                .texelBuffer(sh::kBindingRbfPixelWeights,
                             rbfWeights ? rbfWeights->view() : pts->points())
                .storageImage(sh::kBindingInterpOutput, r.texture(d.output).view)
                .storageImage(sh::kBindingInterpSupport, r.texture(d.support).view);
            // Without rbf_solve the lambda bindings are never read; any valid buffer will do.
            const VkBuffer samplesBuffer = r.buffer(d.samples);
            writer
                .storageBuffer(sh::kBindingLambdaR,
                               d.weights ? r.buffer(d.weights->r) : samplesBuffer)
                .storageBuffer(sh::kBindingLambdaG,
                               d.weights ? r.buffer(d.weights->g) : samplesBuffer)
                .storageBuffer(sh::kBindingLambdaB,
                               d.weights ? r.buffer(d.weights->b) : samplesBuffer);
            // Without motion the motion bindings are never touched either.
            writer
                .storageBuffer(sh::kBindingInterpSampleMotion,
                               d.sampleMotion ? r.buffer(*d.sampleMotion) : samplesBuffer)
                .storageImage(sh::kBindingInterpMotion,
                              r.texture(d.motion ? *d.motion : d.output).view);
            // Nearest neighbour never reads the sites.
            writer.texelBuffer(sh::kBindingInterpSites,
                               d.sites ? r.texelView(*d.sites) : pts->points());
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                         (push.params.x + sh::kInterpGroupX - 1) / sh::kInterpGroupX,
                         (push.params.y + sh::kInterpGroupY - 1) / sh::kInterpGroupY);
        });
    return {data.output, data.support, data.motion};
}

} // namespace gt::passes
