#include "trace/gpu_scene.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstring>

#include "core/error.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::trace {

namespace {
float asFloat(uint32_t v) {
    return std::bit_cast<float>(v);
}

// One BVH's nodes, triangles and shading appended to `p`, its node links offset to where its
// nodes and triangles land (leaves point at triangles, inner nodes at their left child).
void appendGeometry(const scene::Scene& scene, const scene::Bvh& bvh, PackedScene& p) {
    const auto nodeBase = static_cast<uint32_t>(p.nodes.size() / 2);
    const auto triBase = static_cast<uint32_t>(p.triangles.size() / 3);
    for (const scene::BvhNode& n : bvh.nodes()) {
        p.nodes.emplace_back(n.boundsMin,
                             asFloat(n.leftFirst + (n.count > 0 ? triBase : nodeBase)));
        p.nodes.emplace_back(n.boundsMax, asFloat(n.count));
    }
    const auto& order = bvh.triangleOrder();
    for (std::size_t i = 0; i < order.size(); ++i) {
        const scene::BvhTriangle& t = bvh.triangles()[i];
        p.triangles.emplace_back(t.v0, 0.0f);
        p.triangles.emplace_back(t.e1, 0.0f);
        p.triangles.emplace_back(t.e2, 0.0f);
        const scene::Vertex* v = &scene.vertices[3 * order[i]];
        p.shading.emplace_back(v[0].normal, v[0].uv.x);
        p.shading.emplace_back(v[1].normal, v[0].uv.y);
        p.shading.emplace_back(v[2].normal, v[1].uv.x);
        p.shading.emplace_back(v[1].uv.y, v[2].uv.x, v[2].uv.y,
                               asFloat(scene.triangleMaterial[order[i]]));
    }
}

// Everything but the geometry: materials, lights, textures, sky; shared by every LOD level.
PackedScene packShared(const scene::Scene& scene) {
    PackedScene p;
    for (const scene::Material& m : scene.materials) {
        p.materials.push_back(m.baseColor);
        // Metallic -1 marks KHR_materials_unlit: the shading reads this texel anyway, so the flag
        // costs no extra fetch on the hot path.
        p.materials.emplace_back(m.emissive, m.unlit ? -1.0f : m.metallic);
        const uint32_t tex = m.baseColorTexture < 0 ? shaders::trace::kNoTexture
                                                    : static_cast<uint32_t>(m.baseColorTexture);
        p.materials.emplace_back(m.roughness, asFloat(tex), m.alphaCutoff, 0.0f);
    }
    for (const scene::Light& l : scene.lights) {
        p.lights.emplace_back(l.position, asFloat(static_cast<uint32_t>(l.type)));
        p.lights.emplace_back(glm::normalize(l.direction), l.range);
        p.lights.emplace_back(l.color * l.intensity, l.innerConeCos);
        p.lights.emplace_back(l.outerConeCos, 0.0f, 0.0f, 0.0f);
    }
    for (const scene::Texture& t : scene.textures) {
        p.textureInfo.emplace_back(static_cast<uint32_t>(p.texels.size()), t.width, t.height, 0u);
        p.texels.insert(p.texels.end(), t.rgba.begin(), t.rgba.end());
    }
    p.uniforms.skyHorizon = glm::vec4(scene.sky.horizon, scene.sky.ambient);
    p.uniforms.skyZenith = glm::vec4(scene.sky.zenith, scene.exposure);
    p.uniforms.skyGround = glm::vec4(scene.sky.ground, 0.0f);
    p.environment = scene.environment.texels;
    p.uniforms.environment = {scene.environment.width, scene.environment.height, 0u, 0u};
    p.alphaMasked = scene.hasAlphaMask();
    p.uniforms.counts = {
        static_cast<uint32_t>(scene.lights.size()), static_cast<uint32_t>(scene.materials.size()),
        static_cast<uint32_t>(scene.textures.size()), static_cast<uint32_t>(scene.triangleCount())};
    return p;
}

} // namespace

PackedScene packScene(const scene::Scene& scene, const scene::Bvh& bvh) {
    PackedScene p = packShared(scene);
    appendGeometry(scene, bvh, p);
    return p;
}

PackedScene packScene(std::span<const LodGeometry> levels) {
    if (levels.empty() || levels.size() > shaders::trace::kLodLevels) {
        throw Error("packScene: " + std::to_string(levels.size()) + " LOD levels (1 to " +
                    std::to_string(shaders::trace::kLodLevels) + ")");
    }
    // Materials, lights and textures once, from the full-detail level; then each level's trees.
    PackedScene p = packShared(*levels[0].scene);
    uint32_t roots[shaders::trace::kLodLevels] = {};
    for (std::size_t l = 0; l < levels.size(); ++l) {
        roots[l] = static_cast<uint32_t>(p.nodes.size() / 2);
        appendGeometry(*levels[l].scene, *levels[l].bvh, p);
    }
    for (std::size_t l = levels.size(); l < shaders::trace::kLodLevels; ++l) {
        roots[l] = roots[levels.size() - 1];
    }
    p.uniforms.lodRoots = {roots[0], roots[1], roots[2], roots[3]};
    return p;
}

GpuScene::Table GpuScene::upload(vk::Context& ctx, const void* data, std::size_t bytes,
                                 VkFormat format, const char* name) {
    // Empty tables still need a valid view: one zeroed texel.
    const std::size_t size = std::max<std::size_t>(bytes, 16);
    Table t;
    t.buffer = vk::Buffer(
        ctx, {size, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT, vk::MemoryUsage::GpuOnly, name});
    std::vector<std::byte> padded(size, std::byte{0});
    if (bytes > 0) std::memcpy(padded.data(), data, bytes);
    t.buffer.upload(padded);
    t.view = vk::BufferView(ctx, t.buffer, format);
    mBytes += size;
    return t;
}

GpuScene::GpuScene(vk::Context& ctx, const scene::Scene& scene, const scene::Bvh& bvh)
    : GpuScene(ctx, std::span<const LodGeometry>(std::array{LodGeometry{&scene, &bvh}})) {}

GpuScene::GpuScene(vk::Context& ctx, std::span<const LodGeometry> levels) {
    const PackedScene p = packScene(levels);
    mLodLevels = static_cast<uint32_t>(levels.size());
    mAlphaMasked = p.alphaMasked;
    constexpr VkFormat f4 = VK_FORMAT_R32G32B32A32_SFLOAT;
    mNodes = upload(ctx, p.nodes.data(), p.nodes.size() * 16, f4, "scene.bvh_nodes");
    mTriangles = upload(ctx, p.triangles.data(), p.triangles.size() * 16, f4, "scene.triangles");
    mShading = upload(ctx, p.shading.data(), p.shading.size() * 16, f4, "scene.shading");
    mMaterials = upload(ctx, p.materials.data(), p.materials.size() * 16, f4, "scene.materials");
    mLights = upload(ctx, p.lights.data(), p.lights.size() * 16, f4, "scene.lights");
    mTexels = upload(ctx, p.texels.data(), p.texels.size() * 4, VK_FORMAT_R32_UINT, "scene.texels");
    mTextureInfo = upload(ctx, p.textureInfo.data(), p.textureInfo.size() * 16,
                          VK_FORMAT_R32G32B32A32_UINT, "scene.texture_info");
    mEnvironment =
        upload(ctx, p.environment.data(), p.environment.size() * 16, f4, "scene.environment");
    // A storage buffer: see the note on SceneBlock in shaders/common/trace.glsl.
    mUniforms = vk::Buffer(ctx, {sizeof(p.uniforms), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                 vk::MemoryUsage::GpuOnly, "scene.uniforms"});
    mUniforms.upload(std::as_bytes(std::span(&p.uniforms, 1)));
    mBytes += sizeof(p.uniforms);
}

std::vector<VkDescriptorType> tracingBindings(std::initializer_list<VkDescriptorType> own) {
    std::vector<VkDescriptorType> b(shaders::trace::kSceneBindingCount,
                                    VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER);
    b[shaders::trace::kBindingSceneUniforms] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    b.insert(b.end(), own);
    return b;
}

void dispatchImageTrace(vk::Context& ctx, VkCommandBuffer cmd, const vk::ComputePipeline& pipeline,
                        const GpuScene& scene, uint32_t outputBinding, VkImageView output,
                        std::span<const std::byte> push, VkExtent2D extent, VkExtent2D group) {
    vk::DescriptorWriter writer;
    scene.bind(writer);
    writer.storageImage(outputBinding, output);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    writer.push(ctx, cmd, pipeline);
    vk::dispatch(cmd, pipeline, push.data(), static_cast<uint32_t>(push.size()),
                 (extent.width + group.width - 1) / group.width,
                 (extent.height + group.height - 1) / group.height);
}

void GpuScene::bind(vk::DescriptorWriter& w) const {
    namespace t = shaders::trace;
    w.texelBuffer(t::kBindingNodes, mNodes.view.handle())
        .texelBuffer(t::kBindingTriangles, mTriangles.view.handle())
        .texelBuffer(t::kBindingShading, mShading.view.handle())
        .texelBuffer(t::kBindingMaterials, mMaterials.view.handle())
        .texelBuffer(t::kBindingLights, mLights.view.handle())
        .texelBuffer(t::kBindingTexels, mTexels.view.handle())
        .texelBuffer(t::kBindingTextureInfo, mTextureInfo.view.handle())
        .storageBuffer(t::kBindingSceneUniforms, mUniforms.handle())
        .texelBuffer(t::kBindingEnvironment, mEnvironment.view.handle());
}

shaders::trace::CameraPush cameraPush(const scene::Camera& camera, float aspect) {
    const glm::vec3 f = glm::normalize(camera.forward);
    glm::vec3 r = glm::cross(f, camera.up);
    if (glm::length(r) < 1e-6f) r = glm::cross(f, glm::vec3(0, 0, 1));
    r = glm::normalize(r);
    const glm::vec3 u = glm::cross(r, f);
    shaders::trace::CameraPush c{};
    c.origin = glm::vec4(camera.position, std::tan(0.5f * camera.yfov));
    c.forward = glm::vec4(f, aspect);
    c.right = glm::vec4(r, 0.0f);
    c.up = glm::vec4(u, 0.0f);
    return c;
}

FrustumTangents FrustumTangents::symmetric(float yfov, float aspect) {
    const float h = std::tan(0.5f * yfov);
    return {-h * aspect, h * aspect, h, -h};
}

bool FrustumTangents::valid() const noexcept {
    return std::isfinite(left) && std::isfinite(right) && std::isfinite(up) &&
           std::isfinite(down) && left < right && down < up;
}

shaders::trace::CameraPush cameraPush(const scene::Camera& camera, const FrustumTangents& t) {
    const float halfHeight = 0.5f * (t.up - t.down);
    const float halfWidth = 0.5f * (t.right - t.left);
    const float centreX = 0.5f * (t.right + t.left);
    const float centreY = 0.5f * (t.up + t.down);
    scene::Camera c = camera;
    c.yfov = 2.0f * std::atan(halfHeight);
    shaders::trace::CameraPush p = cameraPush(c, halfWidth / halfHeight);
    // Symmetric: overwrite with the exact half extents, so that nothing was rounded twice.
    p.origin.w = halfHeight;
    p.right.w = centreX;
    p.up.w = centreY;
    return p;
}

} // namespace gt::trace
