#pragma once
// Tiny glTF files written by the tests themselves (no shared content needed): a textured-free
// two-triangle quad plus a point light, as .gltf + .bin and as .glb, and broken variants.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "scene/gltf_loader.hpp"

namespace gt::test {

// The one-line error loading `p` gives (empty when it loads).
inline std::string loadError(const std::filesystem::path& p) {
    try {
        (void)scene::loadGltf(p);
    } catch (const LoadError& e) {
        return e.what();
    }
    return {};
}

inline std::vector<uint8_t> quadBin() {
    const float pos[] = {-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1};
    const uint16_t idx[] = {0, 1, 2, 0, 2, 3};
    std::vector<uint8_t> bin(sizeof(pos) + sizeof(idx));
    std::memcpy(bin.data(), pos, sizeof(pos));
    std::memcpy(bin.data() + sizeof(pos), idx, sizeof(idx));
    return bin;
}

inline std::string quadJson(const std::string& bufferUri) {
    const std::string uri = bufferUri.empty() ? "" : "\"uri\": \"" + bufferUri + "\", ";
    return R"({"asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 20}]}},
  "scene": 0, "scenes": [{"nodes": [0, 1]}],
  "nodes": [{"mesh": 0, "scale": [2, 1, 2]}, {"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
  "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1.0, 1.0], "metallicFactor": 0.0}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
  "buffers": [{)" +
           uri + R"("byteLength": 60}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1]},
                {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
}

inline void writeFile(const std::filesystem::path& p, const void* data, std::size_t n) {
    std::ofstream f(p, std::ios::binary);
    f.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
}

// Writes quad.gltf + quad.bin into `dir`; returns the .gltf path.
// Writes quad.bin into `dir` and returns the quad's JSON naming it, to be edited by a test.
inline std::string quadJsonBesideBin(const std::filesystem::path& dir) {
    const auto bin = quadBin();
    writeFile(dir / "quad.bin", bin.data(), bin.size());
    return quadJson("quad.bin");
}

inline std::filesystem::path writeQuadGltf(const std::filesystem::path& dir) {
    const auto bin = quadBin();
    writeFile(dir / "quad.bin", bin.data(), bin.size());
    const std::string json = quadJson("quad.bin");
    writeFile(dir / "quad.gltf", json.data(), json.size());
    return dir / "quad.gltf";
}

// `json`: the JSON chunk (default: the quad's, with an embedded buffer).
inline std::vector<uint8_t> quadGlb(std::string json = quadJson("")) {
    while (json.size() % 4)
        json += ' ';
    auto bin = quadBin();
    while (bin.size() % 4)
        bin.push_back(0);
    std::vector<uint8_t> out;
    auto u32 = [&](uint32_t v) {
        for (int i = 0; i < 4; ++i)
            out.push_back(static_cast<uint8_t>(v >> (8 * i)));
    };
    u32(0x46546C67); // "glTF"
    u32(2);
    u32(static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
    u32(static_cast<uint32_t>(json.size()));
    u32(0x4E4F534A); // "JSON"
    out.insert(out.end(), json.begin(), json.end());
    u32(static_cast<uint32_t>(bin.size()));
    u32(0x004E4942); // "BIN\0"
    out.insert(out.end(), bin.begin(), bin.end());
    return out;
}

} // namespace gt::test
