// Fuzz target: the glTF loader (.gltf JSON or .glb, chosen by the "glTF" magic) and the BVH built
// from what it loads. Contract (gltf_loader.hpp): a broken file throws gt::LoadError naming the
// file; anything loaded is finite and consistent, so the BVH builds and a ray can be traced.
#include <cmath>
#include <cstring>
#include <string>

#include "fuzz_input.hpp"

#include "core/error.hpp"
#include "scene/bvh.hpp"
#include "scene/gltf_loader.hpp"

namespace {

bool finite(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void checkScene(const gt::scene::Scene& s) {
    using gt::fuzz::finding;
    if (s.triangleCount() == 0) finding("a scene without triangles loaded");
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
