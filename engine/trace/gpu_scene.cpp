#include "trace/gpu_scene.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_inverse.hpp>

#include "core/error.hpp"
#include "trace/texture_mips.hpp"
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

void appendLight(const scene::Light& l, std::vector<glm::vec4>& lights) {
    lights.emplace_back(l.position, asFloat(static_cast<uint32_t>(l.type)));
    lights.emplace_back(glm::normalize(l.direction), l.range);
    lights.emplace_back(l.color * l.intensity, l.innerConeCos);
    lights.emplace_back(l.outerConeCos, l.standsInForEmitter ? 1.0f : 0.0f, 0.0f, 0.0f);
}

// Rec. 709 luminance: the emitters' power and the path integrator's Russian roulette and
// firefly clamp weigh colours by it (path.glsl uses the same weights).
float luminance(glm::vec3 c) {
    return glm::dot(c, glm::vec3(0.2126f, 0.7152f, 0.0722f));
}

// The emissive triangles of one BVH (its packed triangles from `triBase` on) as an alias table
// over their emitted power, luminance of the emissive radiance times area (Walker 1977; built
// by Vose 1991's method): texel k = (the probability of keeping entry k, its alias entry, the
// packed triangle of entry k, 0). Picking an entry uniformly and then it or its alias draws a
// triangle with probability power / total in O(1), whatever the number of emitters. The
// triangle's pdf per unit area is then luminance(emissive) / total power, which path.glsl
// computes from the material alone.
void packEmitters(const scene::Scene& scene, const scene::Bvh& bvh, uint32_t triBase,
                  PackedScene& p) {
    std::vector<uint32_t> tris;
    std::vector<double> power;
    const auto& order = bvh.triangleOrder();
    for (std::size_t i = 0; i < order.size(); ++i) {
        // Geometry without its materials (a refined level on its own) emits nothing.
        const uint32_t material = scene.triangleMaterial[order[i]];
        if (material >= scene.materials.size()) continue;
        const scene::Material& m = scene.materials[material];
        const float lum = m.unlit ? 0.0f : luminance(m.emissive);
        const scene::BvhTriangle& t = bvh.triangles()[i];
        const float area = 0.5f * glm::length(glm::cross(t.e1, t.e2));
        if (lum > 0.0f && area > 0.0f) {
            tris.push_back(triBase + static_cast<uint32_t>(i));
            power.push_back(static_cast<double>(lum) * area);
        }
    }
    double total = 0.0;
    for (const double w : power)
        total += w;
    const std::size_t n = tris.size();
    std::vector<double> scaled(n);
    std::vector<uint32_t> alias(n);
    std::vector<std::size_t> small, large;
    for (std::size_t k = 0; k < n; ++k) {
        scaled[k] = power[k] * static_cast<double>(n) / total;
        alias[k] = static_cast<uint32_t>(k);
        (scaled[k] < 1.0 ? small : large).push_back(k);
    }
    while (!small.empty() && !large.empty()) {
        const std::size_t s = small.back(), l = large.back();
        small.pop_back();
        alias[s] = static_cast<uint32_t>(l);
        scaled[l] -= 1.0 - scaled[s];
        if (scaled[l] < 1.0) {
            large.pop_back();
            small.push_back(l);
        }
    }
    // What is left holds probability 1 up to rounding.
    for (const std::size_t k : small)
        scaled[k] = 1.0;
    for (const std::size_t k : large)
        scaled[k] = 1.0;
    p.emitters.clear();
    for (std::size_t k = 0; k < n; ++k) {
        p.emitters.emplace_back(static_cast<float>(scaled[k]), asFloat(alias[k]), asFloat(tris[k]),
                                0.0f);
    }
    const bool transmits =
        std::any_of(scene.materials.begin(), scene.materials.end(), [](const scene::Material& m) {
            return !m.unlit && (m.alphaBlend || (m.transmission > 0.0f && m.metallic < 1.0f));
        });
    p.uniforms.emitters = {static_cast<uint32_t>(n), static_cast<uint32_t>(p.materials.size()),
                           std::bit_cast<uint32_t>(static_cast<float>(total)), transmits ? 1u : 0u};
}

// The environment map's importance-sampling tables for the path integrator (path.glsl,
// sampleEnvironment), appended to `p.environment` after its texels, four floats per texel: a
// marginal CDF over rows, then per row a conditional CDF over columns (Pharr et al., PBR 3rd
// ed., 13.6.7 and 14.2.4), of luminance times sin(theta) (the equirectangular map's solid angle
// per texel) on a grid of at most kEnvironmentCdfWidth x kEnvironmentCdfWidth / 2 cells, each
// the mean of the texels it covers. A floor of 1e-3 of the mean keeps every direction
// sampleable where bilinear filtering spreads light past a cell. SceneUniforms::environment
// z = the first texel of the tables, w = cells across | cells down << 16.
void packEnvironmentCdf(const scene::Environment& env, PackedScene& p) {
    constexpr uint32_t kEnvironmentCdfWidth = 1024;
    const uint32_t w = env.width, h = env.height;
    if (w == 0 || h == 0) return;
    const uint32_t cw = std::min(w, kEnvironmentCdfWidth),
                   ch = std::min(h, kEnvironmentCdfWidth / 2);
    std::vector<double> cell(static_cast<std::size_t>(cw) * ch, 0.0);
    std::vector<uint32_t> count(cell.size(), 0);
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
            const std::size_t c = static_cast<std::size_t>(y * ch / h) * cw + x * cw / w;
            cell[c] += luminance(glm::vec3(env.texels[static_cast<std::size_t>(y) * w + x]));
            ++count[c];
        }
    }
    double mean = 0.0;
    for (std::size_t c = 0; c < cell.size(); ++c) {
        cell[c] = std::max(cell[c], 0.0) / std::max(count[c], 1u);
        mean += cell[c] / static_cast<double>(cell.size());
    }
    std::vector<float> marginal(ch), conditional(cell.size());
    std::vector<double> rows(ch, 0.0);
    for (uint32_t j = 0; j < ch; ++j) {
        const double sinTheta = std::sin(3.14159265358979 * (j + 0.5) / ch);
        std::vector<double> run(cw);
        double sum = 0.0;
        for (uint32_t i = 0; i < cw; ++i) {
            sum += (cell[static_cast<std::size_t>(j) * cw + i] + 1e-3 * mean + 1e-12) * sinTheta;
            run[i] = sum;
        }
        for (uint32_t i = 0; i < cw; ++i)
            conditional[static_cast<std::size_t>(j) * cw + i] =
                i + 1 == cw ? 1.0f : static_cast<float>(run[i] / sum);
        rows[j] = sum;
    }
    double total = 0.0;
    for (uint32_t j = 0; j < ch; ++j) {
        total += rows[j];
        marginal[j] = static_cast<float>(total);
    }
    for (uint32_t j = 0; j < ch; ++j)
        marginal[j] = j + 1 == ch ? 1.0f : static_cast<float>(marginal[j] / total);
    std::vector<float> floats = marginal;
    floats.insert(floats.end(), conditional.begin(), conditional.end());
    floats.resize((floats.size() + 3) / 4 * 4, 1.0f);
    p.uniforms.environment.z = static_cast<uint32_t>(p.environment.size());
    p.uniforms.environment.w = cw | (ch << 16);
    for (std::size_t k = 0; k < floats.size(); k += 4)
        p.environment.emplace_back(floats[k], floats[k + 1], floats[k + 2], floats[k + 3]);
}

uint32_t textureIndex(int texture) {
    return texture < 0 ? shaders::trace::kNoTexture : static_cast<uint32_t>(texture);
}

// Each texture's texels, level 0 then its mip chain (texture_mips.hpp); its info texel says
// where level 0 starts, its size and its levels (trace_shared.h). The direct integrator reads
// level 0 only, so its samples do not change with the chain.
void packTextures(const scene::Scene& scene, PackedScene& p) {
    std::vector<bool> colour(scene.textures.size(), false);
    for (const scene::Material& m : scene.materials) {
        for (const int t : {m.baseColorTexture, m.emissiveTexture}) {
            if (t >= 0 && static_cast<std::size_t>(t) < colour.size()) {
                colour[t] = true;
            }
        }
    }
    for (std::size_t i = 0; i < scene.textures.size(); ++i) {
        const scene::Texture& t = scene.textures[i];
        p.textureInfo.emplace_back(static_cast<uint32_t>(p.texels.size()), t.width, t.height,
                                   mipLevelCount(t.width, t.height));
        p.texels.insert(p.texels.end(), t.rgba.begin(), t.rgba.end());
        const std::vector<uint32_t> chain = mipChain(t, colour[i]);
        p.texels.insert(p.texels.end(), chain.begin(), chain.end());
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
        p.materials.emplace_back(m.roughness, asFloat(tex), m.alphaCutoff, m.specular);
        p.materials.emplace_back(asFloat(textureIndex(m.metallicRoughnessTexture)),
                                 asFloat(textureIndex(m.normalTexture)), m.normalScale,
                                 asFloat(textureIndex(m.emissiveTexture)));
        p.materials.emplace_back(m.transmission, m.ior,
                                 asFloat(textureIndex(m.transmissionTexture)),
                                 m.alphaBlend ? 1.0f : 0.0f);
    }
    for (const scene::Light& l : scene.lights) {
        appendLight(l, p.lights);
    }
    packTextures(scene, p);
    p.uniforms.skyHorizon = glm::vec4(scene.sky.horizon, scene.sky.ambient);
    p.uniforms.skyZenith = glm::vec4(scene.sky.zenith, scene.exposure);
    p.uniforms.skyGround = glm::vec4(scene.sky.ground, 0.0f);
    p.environment = scene.environment.texels;
    p.uniforms.environment = {scene.environment.width, scene.environment.height, 0u, 0u};
    packEnvironmentCdf(scene.environment, p);
    p.alphaMasked = scene.hasAlphaMask();
    p.uniforms.counts = {
        static_cast<uint32_t>(scene.lights.size()), static_cast<uint32_t>(scene.materials.size()),
        static_cast<uint32_t>(scene.textures.size()), static_cast<uint32_t>(scene.triangleCount())};
    return p;
}

// The top three rows of a 4x4 matrix (glm is column-major) into out[at..at+2]: row . (p, 1).
void writeRows(const glm::mat4& m, std::vector<glm::vec4>& out, std::size_t at) {
    for (int r = 0; r < 3; ++r) {
        out[at + r] = glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]);
    }
}

uint32_t nodeCapacity(const scene::Bvh& bvh) {
    // A binary tree over n triangles with non-empty leaves has at most 2n - 1 nodes: room for a
    // rebuild of a deforming bottom level, whose node count may change.
    const std::size_t n = bvh.triangles().size();
    return static_cast<uint32_t>(std::max<std::size_t>({2 * n, 2, bvh.nodes().size()}) - 1);
}

// Bottom level `b`'s nodes at node `nodeBase` (2 texels each) and its triangles and shading at
// triangle `triBase` (3 and 4 texels each), links offset to those places.
void writeBottomLevel(const scene::DynamicGeometry& d, std::size_t b, uint32_t nodeBase,
                      uint32_t triBase, PackedScene& p) {
    const scene::Bvh& bvh = d.bottomLevel(b);
    std::size_t at = 2 * static_cast<std::size_t>(nodeBase);
    for (const scene::BvhNode& n : bvh.nodes()) {
        p.nodes[at++] =
            glm::vec4(n.boundsMin, asFloat(n.leftFirst + (n.count > 0 ? triBase : nodeBase)));
        p.nodes[at++] = glm::vec4(n.boundsMax, asFloat(n.count));
    }
    const std::vector<scene::Vertex>& vertices = d.bottomLevelVertices(b);
    const std::vector<uint32_t>& materials = d.bottomLevelMaterials(b);
    for (std::size_t i = 0; i < bvh.triangles().size(); ++i) {
        const scene::BvhTriangle& t = bvh.triangles()[i];
        const std::size_t tt = 3 * (triBase + i), st = 4 * (triBase + i);
        p.triangles[tt] = glm::vec4(t.v0, 0.0f);
        p.triangles[tt + 1] = glm::vec4(t.e1, 0.0f);
        p.triangles[tt + 2] = glm::vec4(t.e2, 0.0f);
        const scene::Vertex* v = &vertices[3 * i];
        p.shading[st] = glm::vec4(v[0].normal, v[0].uv.x);
        p.shading[st + 1] = glm::vec4(v[1].normal, v[0].uv.y);
        p.shading[st + 2] = glm::vec4(v[2].normal, v[1].uv.x);
        p.shading[st + 3] = glm::vec4(v[1].uv.y, v[2].uv.x, v[2].uv.y, asFloat(materials[i]));
    }
}

// The top level's nodes at layout.topRoot (inner links offset; leaves index the instance
// records, which follow the top level's order) and the instance records.
void writeTopLevel(const scene::DynamicGeometry& d, const DynamicLayout& layout, PackedScene& p) {
    std::size_t at = 2 * static_cast<std::size_t>(layout.topRoot);
    for (const scene::BvhNode& n : d.topLevel()) {
        p.nodes[at++] =
            glm::vec4(n.boundsMin, asFloat(n.leftFirst + (n.count > 0 ? 0u : layout.topRoot)));
        p.nodes[at++] = glm::vec4(n.boundsMax, asFloat(n.count));
    }
    const std::vector<uint32_t>& order = d.topLevelOrder();
    for (std::size_t k = 0; k < order.size(); ++k) {
        const uint32_t instance = order[k];
        const std::size_t r = layout.instanceTexel + k * shaders::trace::kInstanceTexels;
        writeRows(glm::inverse(d.objectToWorld(instance)), p.nodes, r);
        writeRows(d.previousObjectToWorld(instance), p.nodes, r + 3);
        const uint32_t bottom = d.bottomLevelOf(instance);
        p.nodes[r + 6] =
            glm::vec4(asFloat(layout.bottomRoot[bottom]), asFloat(layout.bottomTriangle[bottom]),
                      asFloat(layout.previousTriangle[instance]), asFloat(instance));
        p.nodes[r + 7] = glm::vec4(0.0f);
    }
}

// A deforming instance's triangles one frame ago (its current ones before the first update).
void writePreviousTriangles(const scene::DynamicGeometry& d, const DynamicLayout& layout,
                            PackedScene& p) {
    for (std::size_t instance = 0; instance < d.instanceCount(); ++instance) {
        const uint32_t first = layout.previousTriangle[instance];
        if (first == shaders::trace::kNoPrevious) continue;
        const std::vector<scene::BvhTriangle>& current =
            d.bottomLevel(d.bottomLevelOf(instance)).triangles();
        const std::vector<scene::BvhTriangle>& previous = d.previousTriangles(instance);
        const std::vector<scene::BvhTriangle>& src =
            previous.size() == current.size() ? previous : current;
        for (std::size_t i = 0; i < src.size(); ++i) {
            const std::size_t tt = 3 * (first + i);
            p.triangles[tt] = glm::vec4(src[i].v0, 0.0f);
            p.triangles[tt + 1] = glm::vec4(src[i].e1, 0.0f);
            p.triangles[tt + 2] = glm::vec4(src[i].e2, 0.0f);
        }
    }
}

// Room for the two-level part after the static levels in `p`, its places into `layout`.
void reserveDynamic(const scene::DynamicGeometry& d, DynamicLayout& layout, PackedScene& p) {
    auto nodes = static_cast<uint32_t>(p.nodes.size() / 2);
    auto tris = static_cast<uint32_t>(p.triangles.size() / 3);
    bool deformSeen = false;
    for (std::size_t b = 0; b < d.bottomLevelCount(); ++b) {
        if (d.bottomLevelDeforms(b) && !deformSeen) {
            deformSeen = true;
            layout.dynamicNodeTexel = 2 * nodes;
            layout.dynamicTriangleTexel = 3 * tris;
            layout.dynamicShadingTexel = 4 * tris;
        }
        layout.bottomRoot.push_back(nodes);
        layout.bottomTriangle.push_back(tris);
        const scene::Bvh& bvh = d.bottomLevel(b);
        nodes +=
            d.bottomLevelDeforms(b) ? nodeCapacity(bvh) : static_cast<uint32_t>(bvh.nodes().size());
        tris += static_cast<uint32_t>(bvh.triangles().size());
    }
    if (!deformSeen) {
        layout.dynamicNodeTexel = 2 * nodes;
        layout.dynamicTriangleTexel = 3 * tris;
        layout.dynamicShadingTexel = 4 * tris;
    }
    layout.topRoot = nodes;
    nodes += static_cast<uint32_t>(std::max<std::size_t>(d.topLevelCapacity(), 1));
    layout.instanceTexel = 2 * nodes;
    p.nodes.resize(layout.instanceTexel + d.instanceCount() * shaders::trace::kInstanceTexels);
    p.shading.resize(4 * static_cast<std::size_t>(tris));
    for (std::size_t i = 0; i < d.instanceCount(); ++i) {
        const uint32_t b = d.bottomLevelOf(i);
        if (!d.bottomLevelDeforms(b)) {
            layout.previousTriangle.push_back(shaders::trace::kNoPrevious);
            continue;
        }
        layout.previousTriangle.push_back(tris);
        tris += static_cast<uint32_t>(d.bottomLevel(b).triangles().size());
    }
    p.triangles.resize(3 * static_cast<std::size_t>(tris));
    p.uniforms.dynamic = {layout.topRoot, layout.instanceTexel,
                          static_cast<uint32_t>(d.instanceCount()), 0u};
}

// The rig's lights at its pose: a light with a node sits at the node's origin and shines down
// its -Z (KHR_lights_punctual).
void writeLights(const scene::Scene& scene, const scene::DynamicGeometry& d, PackedScene& p) {
    const std::vector<int>& nodes = d.rig().lightNodes;
    p.lights.clear();
    for (std::size_t i = 0; i < scene.lights.size(); ++i) {
        scene::Light l = scene.lights[i];
        if (i < nodes.size() && nodes[i] >= 0) {
            const glm::mat4& world = d.pose().world.at(static_cast<std::size_t>(nodes[i]));
            l.position = glm::vec3(world[3]);
            l.direction = glm::vec3(world * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f));
        }
        appendLight(l, p.lights);
    }
}

} // namespace

void repackDynamic(const scene::Scene& scene, const scene::DynamicGeometry& d,
                   const DynamicLayout& layout, PackedScene& p) {
    for (std::size_t b = 0; b < d.bottomLevelCount(); ++b) {
        if (!d.bottomLevelDeforms(b)) continue;
        const uint32_t capacity = layout.bottomRoot[b] + nodeCapacity(d.bottomLevel(b));
        if (layout.bottomRoot[b] + d.bottomLevel(b).nodes().size() > capacity) {
            throw Error("gpu scene: bottom level " + std::to_string(b) + " outgrew its nodes");
        }
        writeBottomLevel(d, b, layout.bottomRoot[b], layout.bottomTriangle[b], p);
    }
    if (d.topLevel().size() > std::max<std::size_t>(d.topLevelCapacity(), 1)) {
        throw Error("gpu scene: the top level outgrew its nodes");
    }
    writeTopLevel(d, layout, p);
    writePreviousTriangles(d, layout, p);
    writeLights(scene, d, p);
}

PackedScene packScene(std::span<const LodGeometry> levels, const scene::DynamicGeometry& d,
                      DynamicLayout& layout) {
    PackedScene p = packScene(levels);
    layout = {};
    reserveDynamic(d, layout, p);
    for (std::size_t b = 0; b < d.bottomLevelCount(); ++b) {
        if (!d.bottomLevelDeforms(b)) {
            writeBottomLevel(d, b, layout.bottomRoot[b], layout.bottomTriangle[b], p);
        }
    }
    repackDynamic(*levels[0].scene, d, layout, p);
    return p;
}

PackedScene packScene(const scene::Scene& scene, const scene::Bvh& bvh) {
    PackedScene p = packShared(scene);
    appendGeometry(scene, bvh, p);
    packEmitters(scene, bvh, 0, p);
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
        // The full-detail level's emitters only: a coarser level's lamp is the same surface.
        if (l == 0) packEmitters(*levels[0].scene, *levels[0].bvh, 0, p);
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
    constexpr VkFormat f4 = VK_FORMAT_R32G32B32A32_SFLOAT;
    mNodes = upload(ctx, p.nodes.data(), p.nodes.size() * 16, f4, "scene.bvh_nodes");
    mTriangles = upload(ctx, p.triangles.data(), p.triangles.size() * 16, f4, "scene.triangles");
    mShading = upload(ctx, p.shading.data(), p.shading.size() * 16, f4, "scene.shading");
    mLights = upload(ctx, p.lights.data(), p.lights.size() * 16, f4, "scene.lights");
    uploadShared(ctx, p);
}

// The host-visible copies of the tables that change with the pose, one per frame in flight.
struct GpuScene::DynamicTables {
    struct Copy {
        Table nodes, triangles, shading, lights;
        uint64_t version = 0; // of `packed` it holds
    };
    const scene::Scene* scene = nullptr;
    DynamicLayout layout;
    PackedScene packed; // the latest pose
    uint64_t version = 1;
    std::vector<Copy> copies;
};

namespace {
// A host-visible texel buffer of `bytes` (at least one texel) holding `data`.
vk::Buffer hostTable(vk::Context& ctx, std::span<const glm::vec4> data, const char* name) {
    const std::size_t size = std::max<std::size_t>(data.size_bytes(), 16);
    vk::Buffer b(ctx,
                 {size, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT, vk::MemoryUsage::Upload, name});
    std::vector<std::byte> padded(size, std::byte{0});
    if (!data.empty()) std::memcpy(padded.data(), data.data(), data.size_bytes());
    b.upload(padded);
    return b;
}

// Texels [from, end) of `data` into `buffer` at the same place.
void writeTail(vk::Buffer& buffer, std::span<const glm::vec4> data, std::size_t from) {
    if (from >= data.size()) return;
    buffer.upload(std::as_bytes(data.subspan(from)), from * sizeof(glm::vec4));
}
} // namespace

GpuScene::GpuScene(vk::Context& ctx, std::span<const LodGeometry> levels,
                   const scene::DynamicGeometry& dynamic, uint32_t copies)
    : mDynamic(std::make_unique<DynamicTables>()) {
    if (copies == 0) throw Error("gpu scene: a scene that moves needs at least one table copy");
    DynamicTables& d = *mDynamic;
    d.scene = levels[0].scene;
    d.packed = packScene(levels, dynamic, d.layout);
    mLodLevels = static_cast<uint32_t>(levels.size());
    constexpr VkFormat f4 = VK_FORMAT_R32G32B32A32_SFLOAT;
    auto table = [&](std::span<const glm::vec4> data, const char* name) {
        Table t;
        t.buffer = hostTable(ctx, data, name);
        t.view = vk::BufferView(ctx, t.buffer, f4);
        mBytes += t.buffer.size();
        return t;
    };
    for (uint32_t c = 0; c < copies; ++c) {
        DynamicTables::Copy copy;
        copy.nodes = table(d.packed.nodes, "scene.bvh_nodes");
        copy.triangles = table(d.packed.triangles, "scene.triangles");
        copy.shading = table(d.packed.shading, "scene.shading");
        copy.lights = table(d.packed.lights, "scene.lights");
        copy.version = d.version;
        d.copies.push_back(std::move(copy));
    }
    uploadShared(ctx, d.packed);
}

GpuScene::~GpuScene() = default;

void GpuScene::update(const scene::DynamicGeometry& dynamic) {
    if (!mDynamic) throw Error("gpu scene: update() on a scene where nothing moves");
    repackDynamic(*mDynamic->scene, dynamic, mDynamic->layout, mDynamic->packed);
    ++mDynamic->version;
}

void GpuScene::prepare(uint32_t copy) {
    if (!mDynamic) return;
    DynamicTables& d = *mDynamic;
    DynamicTables::Copy& c = d.copies.at(copy % d.copies.size());
    if (c.version != d.version) {
        writeTail(c.nodes.buffer, d.packed.nodes, d.layout.dynamicNodeTexel);
        writeTail(c.triangles.buffer, d.packed.triangles, d.layout.dynamicTriangleTexel);
        writeTail(c.shading.buffer, d.packed.shading, d.layout.dynamicShadingTexel);
        writeTail(c.lights.buffer, d.packed.lights, 0);
        c.version = d.version;
    }
    mBound = copy % static_cast<uint32_t>(d.copies.size());
}

FittedTextures fitTextures(const PackedScene& p, uint64_t maxTexels) {
    if (p.texels.size() <= maxTexels) {
        return {p.texels, p.textureInfo};
    }
    // Over the device's texel-buffer limit with the mip chains: level 0 alone (the path
    // integrator then filters bilinearly at level 0, as the direct one always does).
    FittedTextures f;
    for (const glm::uvec4& t : p.textureInfo) {
        f.info.emplace_back(static_cast<uint32_t>(f.texels.size()), t.y, t.z, 1u);
        const auto first = p.texels.begin() + t.x;
        f.texels.insert(f.texels.end(), first, first + static_cast<std::ptrdiff_t>(t.y) * t.z);
    }
    if (f.texels.size() > maxTexels) {
        throw Error("the scene's textures need " + std::to_string(f.texels.size()) +
                    " texels, over this device's texel-buffer limit of " +
                    std::to_string(maxTexels) + ": use fewer or smaller textures");
    }
    return f;
}

void GpuScene::uploadShared(vk::Context& ctx, const PackedScene& p) {
    mAlphaMasked = p.alphaMasked;
    constexpr VkFormat f4 = VK_FORMAT_R32G32B32A32_SFLOAT;
    // The emitters' alias table follows the materials (SceneUniforms::emitters).
    std::vector<glm::vec4> materials = p.materials;
    materials.insert(materials.end(), p.emitters.begin(), p.emitters.end());
    mMaterials = upload(ctx, materials.data(), materials.size() * 16, f4, "scene.materials");
    const FittedTextures textures = fitTextures(p, ctx.properties().limits.maxTexelBufferElements);
    mTexels = upload(ctx, textures.texels.data(), textures.texels.size() * 4, VK_FORMAT_R32_UINT,
                     "scene.texels");
    mTextureInfo = upload(ctx, textures.info.data(), textures.info.size() * 16,
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
                        const GpuScene& scene, std::initializer_list<TracedImage> outputs,
                        std::span<const std::byte> push, VkExtent2D extent, VkExtent2D group) {
    vk::DescriptorWriter writer;
    scene.bind(writer);
    for (const TracedImage& o : outputs)
        writer.storageImage(o.binding, o.view);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    writer.push(ctx, cmd, pipeline);
    vk::dispatch(cmd, pipeline, push.data(), static_cast<uint32_t>(push.size()),
                 (extent.width + group.width - 1) / group.width,
                 (extent.height + group.height - 1) / group.height);
}

std::vector<uint32_t> tracingSpecialization(std::vector<uint32_t> passConstants, bool dynamic,
                                            const IntegratorSettings& integrator) {
    namespace t = shaders::trace;
    passConstants.resize(std::max<std::size_t>(passConstants.size(), t::kSpecDynamic + 1));
    passConstants[t::kSpecDynamic] = dynamic ? 1u : 0u;
    if (integrator.integrator == Integrator::Direct) return passConstants;
    if (integrator.bounces < 1 || integrator.bounces > kMaxBounces) {
        throw ArgumentError("bounces must be 1 to " + std::to_string(kMaxBounces));
    }
    if (!(integrator.fireflyClamp >= 0.0f) || !std::isfinite(integrator.fireflyClamp)) {
        throw ArgumentError("the firefly clamp must be 0 (off) or a positive luminance");
    }
    passConstants.resize(std::max<std::size_t>(passConstants.size(), t::kSpecSequence + 1));
    passConstants[t::kSpecIntegrator] = static_cast<uint32_t>(integrator.integrator);
    passConstants[t::kSpecBounces] = integrator.bounces;
    passConstants[t::kSpecFireflyClamp] = std::bit_cast<uint32_t>(integrator.fireflyClamp);
    passConstants[t::kSpecSequence] = static_cast<uint32_t>(integrator.sequence);
    return passConstants;
}

void GpuScene::bind(vk::DescriptorWriter& w) const {
    namespace t = shaders::trace;
    const bool copy = mDynamic != nullptr;
    const DynamicTables::Copy* c = copy ? &mDynamic->copies[mBound] : nullptr;
    w.texelBuffer(t::kBindingNodes, (copy ? c->nodes : mNodes).view.handle())
        .texelBuffer(t::kBindingTriangles, (copy ? c->triangles : mTriangles).view.handle())
        .texelBuffer(t::kBindingShading, (copy ? c->shading : mShading).view.handle())
        .texelBuffer(t::kBindingMaterials, mMaterials.view.handle())
        .texelBuffer(t::kBindingLights, (copy ? c->lights : mLights).view.handle())
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
