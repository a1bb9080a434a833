// Fuzz target: the glTF loader (.gltf JSON or .glb, chosen by the "glTF" magic) and the BVH built
// from what it loads. Contract (gltf_loader.hpp): a broken file throws gt::LoadError naming the
// file; anything loaded is finite and consistent, so the BVH builds and a ray can be traced.
#include <cmath>
#include <cstring>
#include <string>

#include "fuzz_input.hpp"

#include "core/error.hpp"
#include "scene/animation.hpp"
#include "scene/bvh.hpp"
#include "scene/gltf_loader.hpp"

namespace {

bool finite(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// What the animation code indexes without checking (animation.hpp: the loader validated it).
void checkRigIndices(const gt::scene::Rig& rig) {
    using gt::fuzz::finding;
    for (std::size_t i = 0; i < rig.nodes.size(); ++i) {
        if (rig.nodes[i].parent >= static_cast<int>(i)) finding("a node before its parent");
    }
    for (const auto& skin : rig.skins) {
        if (skin.inverseBind.size() != skin.joints.size()) finding("a skin's matrices and joints");
        for (const uint32_t j : skin.joints) {
            if (j >= rig.nodes.size()) finding("a skin's joint is not a node");
        }
    }
    for (const auto& a : rig.animations) {
        for (const auto& c : a.channels) {
            if (c.sampler >= a.samplers.size() || c.node >= rig.nodes.size()) {
                finding("a channel names a sampler or node that does not exist");
            }
            const auto& s = a.samplers[c.sampler];
            const std::size_t per =
                s.interpolation == gt::scene::Interpolation::CubicSpline ? 3 : 1;
            if (s.times.empty() || s.values.size() != s.times.size() * s.components * per) {
                finding("a played sampler's keys and values disagree");
            }
        }
    }
    for (const auto& inst : rig.instances) {
        if (inst.node >= rig.nodes.size() || inst.mesh >= rig.meshes.size() ||
            inst.skin >= static_cast<int>(rig.skins.size())) {
            finding("an instance names what does not exist");
        }
        const auto& m = rig.meshes[inst.mesh];
        if (m.vertices.size() != 3 * m.triangleMaterial.size()) finding("a rig mesh's counts");
        if (inst.skin < 0) continue;
        if (m.joints.size() != m.vertices.size() || m.weights.size() != m.vertices.size()) {
            finding("a skinned mesh without a joint per vertex");
        }
        for (const auto& j : m.joints) {
            for (int c = 0; c < 4; ++c) {
                if (j[c] >= rig.skins[static_cast<std::size_t>(inst.skin)].joints.size()) {
                    finding("a joint out of range of its skin");
                }
            }
        }
    }
}

// The rig posed at two instants: every instance deforms without a fault.
void poseRig(const gt::scene::Rig& rig) {
    checkRigIndices(rig);
    for (const double t : {0.0, 0.37}) {
        const gt::scene::Pose pose = gt::scene::evaluatePose(rig, {}, t);
        std::vector<gt::scene::Vertex> out;
        for (const auto& inst : rig.instances) {
            gt::scene::deformInstance(rig, inst, pose, out);
            if (out.size() != rig.meshes[inst.mesh].vertices.size()) {
                gt::fuzz::finding("a deformed instance changed its vertex count");
            }
        }
    }
}

void checkScene(const gt::scene::Scene& s) {
    using gt::fuzz::finding;
    // An animated file's moving meshes are in its rig, not among the static triangles.
    const std::size_t moving = s.rig ? s.rig->instances.size() : 0;
    if (s.triangleCount() == 0 && moving == 0) finding("a scene without triangles loaded");
    if (s.rig && s.rig->lightNodes.size() != s.lights.size()) finding("a light without its node");
    if (s.rig) poseRig(*s.rig);
    if (s.vertices.size() != 3 * s.triangleCount()) finding("vertex and triangle counts disagree");
    for (const auto& v : s.vertices) {
        if (!finite(v.position) || !finite(v.normal) || !std::isfinite(v.uv.x) ||
            !std::isfinite(v.uv.y)) {
            finding("a vertex that is not finite loaded");
        }
    }
    for (const uint32_t m : s.triangleMaterial) {
        if (m >= s.materials.size()) finding("a triangle names a material that does not exist");
    }
    for (const auto& m : s.materials) {
        if (m.baseColorTexture >= static_cast<int>(s.textures.size())) {
            finding("a material names a texture that does not exist");
        }
    }
    for (const auto& t : s.textures) {
        if (t.rgba.size() != static_cast<std::size_t>(t.width) * t.height) {
            finding("a texture's size and its pixels disagree");
        }
    }
    for (const auto& l : s.lights) {
        if (!finite(l.position) || !finite(l.direction) || !finite(l.color) ||
            !std::isfinite(l.intensity)) {
            finding("a light that is not finite loaded");
        }
    }
    if (!finite(s.camera.position) || !finite(s.camera.forward) || !std::isfinite(s.camera.yfov)) {
        finding("a camera that is not finite loaded");
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    const auto file = gt::fuzz::InputFile::write({data, size}, glb ? "input.glb" : "input.gltf");
    try {
        gt::scene::GltfLoadReport report;
        // The shipped limits (20 M triangles, 1 M node instances) are for real scenes; fuzzing
        // explores the loader's logic, not how long a 20 M-triangle BVH takes, so inputs get a
        // smaller budget, textures included (a fuzzer's memory limit is about 2 GB).
        const gt::scene::Scene scene = gt::scene::loadGltf(
            file, &report,
            {.maxTriangles = 100000, .maxInstances = 100000, .maxTextureBytes = 64 << 20});
        checkScene(scene);
        const gt::scene::Bvh bvh(scene); // a node at 3.4e38 crashed here
        (void)bvh.intersect({scene.camera.position, scene.camera.forward});
    } catch (const gt::LoadError& e) {
        if (std::string(e.what()).find(file.string()) == std::string::npos) {
            gt::fuzz::finding(std::string("error does not name the file: ") + e.what());
        }
    } catch (const std::exception& e) {
        gt::fuzz::finding(std::string("not a LoadError: ") + e.what());
    }
    return 0;
}
