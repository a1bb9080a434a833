// Writes the fuzz targets' seed corpora and regression cases:
//   gazetrace_fuzz_corpus OUT
// makes OUT/<target>/seeds (small valid files that reach deep into each reader) and
// OUT/<target>/regressions (every hostile input found so far that touches a fuzzed reader, rebuilt
// here from its description, plus what fuzzing found since). Nothing is copied from ../shared:
// every byte is made by this program, so the corpus is the same on every machine.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <stb_image_write.h>

#include "fuzz_params.hpp"
#include "support/gltf_fixtures.hpp"

#include "foveation/point_set_cache.hpp"
#include "gaze/calibration.hpp"
#include "net/udp_emitter.hpp"
#include <nlohmann/json.hpp>

namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

fs::path gOut;

void put(const std::string& target, const std::string& kind, const std::string& name,
         const void* data, std::size_t size) {
    const fs::path dir = gOut / target / kind;
    fs::create_directories(dir);
    std::ofstream f(dir / name, std::ios::binary | std::ios::trunc);
    f.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!f.flush()) {
        std::fprintf(stderr, "gazetrace_fuzz_corpus: cannot write %s\n", (dir / name).c_str());
        std::exit(1);
    }
}
void put(const std::string& target, const std::string& kind, const std::string& name,
         const std::string& text) {
    put(target, kind, name, text.data(), text.size());
}
void put(const std::string& target, const std::string& kind, const std::string& name,
         const Bytes& bytes) {
    put(target, kind, name, bytes.data(), bytes.size());
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
    const auto at = s.find(from);
    if (at == std::string::npos) {
        std::fprintf(stderr, "gazetrace_fuzz_corpus: '%s' not in its template\n", from.c_str());
        std::exit(1);
    }
    return s.replace(at, from.size(), to);
}

template <typename T> void append(Bytes& b, const T& v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    b.insert(b.end(), p, p + sizeof(T));
}

std::string base64(const Bytes& in) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < in.size(); i += 3) {
        const std::uint32_t n = (std::uint32_t{in[i]} << 16) |
                                (i + 1 < in.size() ? std::uint32_t{in[i + 1]} << 8 : 0) |
                                (i + 2 < in.size() ? std::uint32_t{in[i + 2]} : 0);
        out += k[(n >> 18) & 63];
        out += k[(n >> 12) & 63];
        out += i + 1 < in.size() ? k[(n >> 6) & 63] : '=';
        out += i + 2 < in.size() ? k[n & 63] : '=';
    }
    return out;
}

std::string dataUri(const Bytes& b, const std::string& mime = "application/octet-stream") {
    return "data:" + mime + ";base64," + base64(b);
}

Bytes toBytes(const void* data, int size) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    return {p, p + size};
}

void appendTo(void* ctx, void* data, int size) {
    auto* b = static_cast<Bytes*>(ctx);
    const Bytes more = toBytes(data, size);
    b->insert(b->end(), more.begin(), more.end());
}

Bytes png(int w, int h) {
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w) * h * 4);
    for (std::size_t i = 0; i < rgba.size(); ++i)
        rgba[i] = static_cast<std::uint8_t>((i * 37) % 251);
    Bytes out;
    stbi_write_png_to_func(appendTo, &out, w, h, 4, rgba.data(), w * 4);
    return out;
}

// A PNG whose header claims `w` x `h` and which has no pixel data at all.
Bytes pngHeaderOnly(std::uint32_t w, std::uint32_t h) {
    auto crc = [](const Bytes& b, std::size_t from) {
        std::uint32_t c = 0xFFFFFFFFu;
        for (std::size_t i = from; i < b.size(); ++i) {
            c ^= b[i];
            for (int k = 0; k < 8; ++k)
                c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
        }
        return c ^ 0xFFFFFFFFu;
    };
    auto be32 = [](Bytes& b, std::uint32_t v) {
        for (int s = 24; s >= 0; s -= 8)
            b.push_back(static_cast<std::uint8_t>(v >> s));
    };
    Bytes b = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    be32(b, 13);
    const std::size_t type = b.size();
    b.insert(b.end(), {'I', 'H', 'D', 'R'});
    be32(b, w);
    be32(b, h);
    b.insert(b.end(), {8, 6, 0, 0, 0}); // 8-bit RGBA
    be32(b, crc(b, type));
    be32(b, 0);
    const std::size_t end = b.size();
    b.insert(b.end(), {'I', 'E', 'N', 'D'});
    be32(b, crc(b, end));
    return b;
}

// ---- glTF ------------------------------------------------------------------------------------

std::string quadEmbedded() {
    return gt::test::quadJson(dataUri(gt::test::quadBin()));
}

// The quad with UVs and a PNG texture (data URIs for both), a camera, three kinds of light, a
// node hierarchy with matrix / TRS transforms, emissive strength, unlit and texture transform.
std::string featureful() {
    Bytes bin = gt::test::quadBin(); // 48 B positions, 12 B indices
    for (const float uv : {0.f, 0.f, 1.f, 0.f, 1.f, 1.f, 0.f, 1.f})
        append(bin, uv);
    return R"({"asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_unlit", "KHR_texture_transform"],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 20, "range": 9},
     {"type": "spot", "color": [1, 0.5, 0.2], "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
     {"type": "directional", "intensity": 3}]}},
  "scene": 0, "scenes": [{"nodes": [0, 3]}],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.1, "aspectRatio": 1.5}}],
  "nodes": [{"children": [1, 2], "rotation": [0, 0.3826834, 0, 0.9238795], "scale": [2, 1, 2]},
            {"mesh": 0, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0.5,0,1]},
            {"mesh": 1, "translation": [0, 1, -2]},
            {"camera": 0, "translation": [0, 1, 4],
             "children": [4, 5, 6]},
            {"extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"translation": [1, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"rotation": [-0.7071068, 0, 0, 0.7071068], "extensions": {"KHR_lights_punctual": {"light": 2}}}],
  "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
                   "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 2], "rotation": 0.3}}},
                   "metallicFactor": 0.2, "roughnessFactor": 0.7},
                 "emissiveFactor": [1, 0.5, 0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}},
                {"alphaMode": "MASK", "alphaCutoff": 0.4, "extensions": {"KHR_materials_unlit": {}}}],
  "textures": [{"source": 0, "sampler": 0}], "samplers": [{"wrapS": 33648}],
  "images": [{"uri": ")" +
           dataUri(png(4, 4), "image/png") + R"("}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 2}, "indices": 1, "material": 0}]},
             {"primitives": [{"attributes": {"POSITION": 0}, "mode": 6, "material": 1},
                             {"attributes": {"POSITION": 0}, "mode": 5}]}],
  "buffers": [{"uri": ")" +
           dataUri(bin) + R"(", "byteLength": 92}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12},
                  {"buffer": 0, "byteOffset": 60, "byteLength": 32}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1]},
                {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
                {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}]})";
}

// Normalised short positions (KHR_mesh_quantization) with a sparse accessor moving one vertex.
std::string quantizedSparse() {
    Bytes bin;
    for (const std::int16_t v :
         {-32767, 0, -32767, 32767, 0, -32767, 32767, 0, 32767, -32767, 0, 32767})
        append(bin, v);                              // 24 B
    for (const std::uint16_t i : {0, 1, 2, 0, 2, 3}) // 12 B
        append(bin, i);
    append(bin, std::uint16_t{2});                        // sparse index, 2 B
    append(bin, std::uint16_t{0});                        // padding to 4
    for (const std::int16_t v : {16000, 16000, 16000, 0}) // sparse value (+ padding)
        append(bin, v);
    return R"({"asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_mesh_quantization"], "extensionsRequired": ["KHR_mesh_quantization"],
  "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "buffers": [{"uri": ")" +
           dataUri(bin) + R"(", "byteLength": 48}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 24}, {"buffer": 0, "byteOffset": 24, "byteLength": 12},
                  {"buffer": 0, "byteOffset": 36, "byteLength": 2}, {"buffer": 0, "byteOffset": 40, "byteLength": 6}],
  "accessors": [{"bufferView": 0, "componentType": 5122, "normalized": true, "count": 4, "type": "VEC3",
                 "min": [-1, 0, -1], "max": [1, 0.5, 1],
                 "sparse": {"count": 1, "indices": {"bufferView": 2, "componentType": 5123},
                            "values": {"bufferView": 3}}},
                {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
}

// Sizes and offsets that wrap around in 64-bit arithmetic, so a bounds check written with `+`
// and `*` passes: count x 3 of (2^64 + 2) / 3 is 2 floats (the loader wrote past them), a
// bufferView at byteOffset 2^64 - 4 read before its buffer; and what tinygltf reads as 0 or
// casts to int (negative offsets, 64-bit indices).
void wrapAround(const std::string& t, const std::string& quad) {
    const std::string position = R"("count": 4, "type": "VEC3")";
    const std::string view0 = R"({"buffer": 0, "byteOffset": 0, "byteLength": 48})";
    const std::string accessor0 = R"({"bufferView": 0, "componentType": 5126,)";
    put(t, "regressions", "accessor_count_x3_wraps_to_2.gltf",
        replaced(quad, position, R"("count": 6148914691236517206, "type": "VEC3")"));
    put(t, "regressions", "index_count_x2_wraps_to_0.gltf",
        replaced(quad, R"("count": 6, "type": "SCALAR")",
                 R"("count": 9223372036854775809, "type": "SCALAR")"));
    put(t, "regressions", "view_offset_plus_length_wraps.gltf",
        replaced(quad, view0,
                 R"({"buffer": 0, "byteOffset": 18446744073709551612, "byteLength": 52})"));
    put(t, "regressions", "accessor_offset_wraps.gltf",
        replaced(
            quad, accessor0,
            R"({"bufferView": 0, "byteOffset": 18446744073709551612, "componentType": 5126,)"));
    put(t, "regressions", "sparse_offset_wraps.gltf",
        replaced(quad, position, R"("count": 4, "type": "VEC3", "sparse": {"count": 4,
            "indices": {"bufferView": 1, "componentType": 5125, "byteOffset": 18446744073709551612},
            "values": {"bufferView": 0}})"));
    put(t, "regressions", "sparse_count_x12_wraps.gltf",
        replaced(quad, position,
                 R"("count": 4, "type": "VEC3", "sparse": {"count": 1537228672809129302,
            "indices": {"bufferView": 1, "componentType": 5121}, "values": {"bufferView": 0}})"));
    put(t, "regressions", "image_view_offset_wraps.gltf",
        replaced(quad, R"({"buffer": 0, "byteOffset": 48, "byteLength": 12}])",
                 R"({"buffer": 0, "byteOffset": 48, "byteLength": 12},
                    {"buffer": 0, "byteOffset": 18446744073709551612, "byteLength": 8}],
                    "images": [{"bufferView": 2, "mimeType": "image/png"}])"));
    put(t, "regressions", "negative_accessor_offset.gltf",
        replaced(quad, accessor0, R"({"bufferView": 0, "byteOffset": -4, "componentType": 5126,)"));
    put(t, "regressions", "negative_view_offset.gltf",
        replaced(quad, view0, R"({"buffer": 0, "byteOffset": -8, "byteLength": 48})"));
    put(t, "regressions", "negative_stride.gltf",
        replaced(quad, view0, R"({"buffer": 0, "byteLength": 48, "byteStride": -12})"));
    put(t, "regressions", "index_2pow32_plus_1.gltf",
        replaced(quad, R"("indices": 1)", R"("indices": 4294967297)"));
    put(t, "regressions", "matrix_of_15.gltf",
        replaced(quad, R"({"mesh": 0, "scale": [2, 1, 2]})",
                 R"({"mesh": 0, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 5,0,0]})"));
    put(t, "regressions", "morph_target_missing_accessor.gltf",
        replaced(quad, R"("indices": 1)", R"("indices": 1, "targets": [{"POSITION": 9}])"));
    put(t, "regressions", "spot_inner_above_outer.gltf",
        replaced(quad, R"({"type": "point", "intensity": 20})",
                 R"({"type": "spot", "spot": {"innerConeAngle": 0.7, "outerConeAngle": 0.3}})"));
    // GLB headers: versions other than 2, chunk lengths near 2^32 (a 32-bit sum wraps).
    const Bytes glb = gt::test::quadGlb();
    const auto withWord = [&](std::size_t offset, std::uint32_t v) {
        Bytes b = glb;
        std::memcpy(b.data() + offset, &v, 4);
        return b;
    };
    std::uint32_t jsonLength = 0;
    std::memcpy(&jsonLength, glb.data() + 12, 4);
    put(t, "regressions", "glb_version_1.glb", withWord(4, 1));
    put(t, "regressions", "glb_version_99.glb", withWord(4, 99));
    put(t, "regressions", "glb_json_chunk_2pow32_minus_4.glb", withWord(12, 0xFFFFFFFCu));
    put(t, "regressions", "glb_bin_chunk_2pow32_minus_16.glb",
        withWord(20 + std::size_t{jsonLength}, 0xFFFFFFF0u));
    put(t, "regressions", "glb_length_2pow32_minus_1.glb", withWord(8, 0xFFFFFFFFu));
    put(t, "regressions", "bom.gltf", "\xEF\xBB\xBF" + quad);
}

void gltf() {
    const std::string t = "gltf";
    const std::string quad = quadEmbedded();
    put(t, "seeds", "quad_embedded.gltf", quad);
    put(t, "seeds", "quad.glb", gt::test::quadGlb());
    put(t, "seeds", "featureful.gltf", featureful());
    put(t, "seeds", "quantized_sparse.gltf", quantizedSparse());
    // Animation, a skin and a morph target: the rig the loader builds and the poses of it.
    std::ifstream sample(fs::path(GT_SOURCE_DIR) / "content" / "animated" / "moving_parts.gltf");
    put(t, "seeds", "moving_parts.gltf",
        std::string(std::istreambuf_iterator<char>(sample), std::istreambuf_iterator<char>()));

    // A node near the float limit crashed the BVH build (binning with a zero scale).
    const std::string home = R"({"mesh": 0, "scale": [2, 1, 2]})";
    put(t, "regressions", "far_node_3.4e38.gltf",
        replaced(quad, home, R"({"mesh": 0, "translation": [3.4e38, 0, 0], "name": "far"})"));
    put(t, "regressions", "far_node_2e38.gltf",
        replaced(quad, home, R"({"mesh": 0, "translation": [2e38, 0, 0]})"));
    put(t, "regressions", "far_scale_1e39.gltf",
        replaced(quad, home, R"({"mesh": 0, "scale": [1e39, 1, 1]})"));
    // JSON nested 20,000 deep overflowed the stack inside tinygltf's parser.
    const std::string asset = R"("asset": {"version": "2.0"})";
    const std::string deep = std::string(20000, '[') + std::string(20000, ']');
    put(t, "regressions", "deep_json_20000.gltf",
        replaced(quad, asset, R"("asset": {"version": "2.0", "extras": )" + deep + "}"));
    put(t, "regressions", "deep_json_20000.glb",
        gt::test::quadGlb(replaced(gt::test::quadJson(""), asset,
                                   R"("asset": {"version": "2.0", "extras": )" + deep + "}")));
    // A POSITION accessor without a bufferView and a count of 178,956,969: 122 s and 4.3 GB.
    put(t, "regressions", "no_buffer_view_count_178956969.gltf",
        replaced(quad, R"({"bufferView": 0, "componentType": 5126, "count": 4,)",
                 R"({"componentType": 5126, "count": 178956969,)"));
    put(t, "regressions", "accessor_count_2pow62.gltf",
        replaced(quad, R"("count": 4, "type": "VEC3")",
                 R"("count": 4611686018427387904, "type": "VEC3")"));
    // Each level references the next twice, 24 levels: 2^24 instances, bad_alloc after 135 s.
    std::string nodes = R"("nodes": [)";
    for (int i = 0; i < 24; ++i)
        nodes += R"({"children": [)" + std::to_string(i + 1) + "," + std::to_string(i + 1) + "]},";
    nodes += R"({"mesh": 0}])";
    std::string dag = quad;
    const auto from = dag.find(R"("nodes": [{"mesh")");
    dag.replace(from, dag.find("],\n", from) + 1 - from, nodes);
    put(t, "regressions", "dag_24_levels.gltf",
        replaced(dag, R"("scenes": [{"nodes": [0, 1]}])", R"("scenes": [{"nodes": [0]}])"));
    // Found by fuzzing: the same graph over a mesh without primitives is 2^24 visits and no
    // triangle, which the triangle count let through (11 s a file).
    put(t, "regressions", "dag_24_levels_no_triangles.gltf",
        replaced(replaced(dag, R"("scenes": [{"nodes": [0, 1]}])", R"("scenes": [{"nodes": [0]}])"),
                 R"("primitives")", R"("primithves")"));
    // Found by fuzzing: a light colour of 1.7e117 became an infinite float.
    put(t, "regressions", "light_color_1.7e117.gltf",
        replaced(featureful(), R"("color": [1, 0.5, 0.2])", R"("color": [1.7e117, 0.5, 0.2])"));
    // Found by fuzzing: a texture coordinate of NaN (float bits 0x7F8D0000) in the buffer loaded
    // into a vertex.
    put(t, "regressions", "texcoord_nan.gltf",
        replaced(featureful(), "gD8AAIA/AAAAAAAAgD8=", "gD8AAI1/AAAAAAAAgD8="));
    // Found by fuzzing (UBSan): a light reference of 1.5e44 went through tinygltf's int cast.
    put(t, "regressions", "light_index_1.5e44.gltf",
        replaced(quad, R"("KHR_lights_punctual": {"light": 0})",
                 R"("KHR_lights_punctual": {"light": 1.5e44})"));
    // One mesh referenced by 2,000 and 20,000 primitives (3,000 triangles each).
    Bytes many;
    for (int i = 0; i < 3000; ++i)
        for (const float v :
             {i * 1e-3f, 0.f, 0.f, i * 1e-3f, 1.f, 0.f, i * 1e-3f + 1e-3f, 0.f, 0.f})
            append(many, v);
    for (const int n : {2000, 20000}) {
        std::string prims;
        for (int i = 0; i < n; ++i)
            prims += std::string(i ? "," : "") + R"({"attributes": {"POSITION": 0}})";
        put(t, "regressions", "one_mesh_" + std::to_string(n) + "_primitives.gltf",
            R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0}], "meshes": [{"primitives": [)" +
                prims + R"(]}],
  "buffers": [{"uri": ")" +
                dataUri(many) + R"(", "byteLength": )" + std::to_string(many.size()) + R"(}],
  "bufferViews": [{"buffer": 0, "byteLength": )" +
                std::to_string(many.size()) + R"(}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 9000, "type": "VEC3",
                 "min": [0, 0, 0], "max": [3.001, 1, 0]}]})");
    }
    // The quad with a base-colour texture whose image is `uri`.
    const auto textured = [&](const std::string& uri) {
        return replaced(
            replaced(
                quad, R"({"pbrMetallicRoughness": {"baseColorFactor")",
                R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "baseColorFactor")"),
            R"("buffers")",
            R"("images": [{"uri": ")" + uri + R"("}], "textures": [{"source": 0}], "buffers")");
    };
    // An image URI leaving the model's folder was read.
    put(t, "regressions", "image_uri_outside_folder.gltf", textured("../../../../etc/shadow"));
    // A texture whose header claims 23000 x 23000 pixels: stb asks for 2 GB before reading.
    put(t, "regressions", "texture_claims_23000x23000.gltf",
        textured(dataUri(pngHeaderOnly(23000, 23000), "image/png")));
    wrapAround(t, quad);
}

// ---- Radiance ----------------------------------------------------------------------------------

Bytes hdr(int w, int h) {
    std::vector<float> rgb(static_cast<std::size_t>(w) * h * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i)
        rgb[i] = (i / 3) % 5 < 3 ? 0.5f : std::exp2(static_cast<float>(i % 13) - 6.0f);
    Bytes out;
    stbi_write_hdr_to_func(appendTo, &out, w, h, 3, rgb.data());
    return out;
}

Bytes text(const std::string& s) {
    return {s.begin(), s.end()};
}

void radiance() {
    const std::string t = "radiance";
    const Bytes rle = hdr(16, 8); // new-style runs (width 8..32767)
    put(t, "seeds", "runs_16x8.hdr", rle);
    put(t, "seeds", "flat_4x2.hdr", hdr(4, 2)); // flat pixels (width < 8)
    // Old-style runs: a pixel, then (1, 1, 1, n) repeating it n times.
    Bytes old = text("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 6\n");
    old.insert(old.end(), {128, 64, 32, 129, 1, 1, 1, 5});
    put(t, "seeds", "old_style_run_6x1.hdr", old);

    // stb_image loops forever on a truncated run-length file.
    put(t, "regressions", "truncated_runs.hdr", Bytes(rle.begin(), rle.begin() + rle.size() / 2));
    Bytes zeroRun = text("#?RADIANCE\n\n-Y 1 +X 8\n");
    zeroRun.insert(zeroRun.end(), {2, 2, 0, 8, 128, 0});
    put(t, "regressions", "zero_length_run.hdr", zeroRun);
    // A 40-byte header promising 16384 x 8192 took 1.5 GiB; 32768 x 32768 asked for 12 GiB.
    Bytes promise = text("#?RADIANCE\n\n-Y 8192 +X 16384\n");
    promise.insert(promise.end(), {2, 2, 0x40, 0x00, 0x81, 0x01});
    put(t, "regressions", "header_16384x8192_no_data.hdr", promise);
    put(t, "regressions", "header_32768x32768.hdr", text("#?RADIANCE\n\n-Y 32768 +X 32768\n"));
}

// ---- point-set cache -----------------------------------------------------------------------

Bytes readAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void pointSetCache() {
    const std::string t = "point_set_cache";
    const auto params = gt::fuzz::pointSetParams();
    const gt::foveation::PointSet set = gt::foveation::PointSet::generate(params);
    const fs::path tmp = gOut / "point_set.tmp";
    gt::foveation::savePointSet(tmp, set);
    Bytes file = readAll(tmp);
    fs::remove(tmp);
    file.resize(file.size() - 8); // the target appends the checksum
    put(t, "seeds", "generated.gtps", file);
    const std::size_t first = file.size() - 12 * set.points().size();
    const std::size_t countAt = first - 8;
    auto withPoint = [&](std::size_t i, int field, float v) {
        Bytes b = file;
        std::memcpy(b.data() + first + 12 * i + 4 * static_cast<std::size_t>(field), &v, 4);
        return b;
    };
    auto withCount = [&](std::uint64_t n) {
        Bytes b(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(first));
        std::memcpy(b.data() + countAt, &n, 8);
        b.insert(b.end(), file.begin() + static_cast<std::ptrdiff_t>(first),
                 file.begin() + static_cast<std::ptrdiff_t>(
                                    first + 12 * std::min<std::uint64_t>(n, set.points().size())));
        return b;
    };
    put(t, "seeds", "two_points.gtps", withCount(2));
    // Valid checksum, impossible contents: the neighbour search ran unbounded.
    put(t, "regressions", "nan_point.gtps",
        withPoint(7, 0, std::numeric_limits<float>::quiet_NaN()));
    put(t, "regressions", "point_times_1e30.gtps", withPoint(3, 1, set.points()[3].y * 1e30f));
    put(t, "regressions", "infinite_spacing.gtps",
        withPoint(5, 2, std::numeric_limits<float>::infinity()));
    put(t, "regressions", "zero_points.gtps", withCount(0));
    put(t, "regressions", "one_point.gtps", withCount(1));
    Bytes huge = file;
    const std::uint64_t n = std::uint64_t{1} << 60;
    std::memcpy(huge.data() + countAt, &n, 8);
    put(t, "regressions", "count_2pow60.gtps", huge);
}

// ---- gaze traces -----------------------------------------------------------------------------

void gazeTrace() {
    const std::string t = "gaze_trace";
    put(t, "seeds", "pixels.csv", "t_ms,x,y\n0,640,720\n33.3,650.5,719\n66.7,900,400\n");
    put(t, "seeds", "angles.csv",
        "# recorded by gazetrace track\r\nt_ms,yaw_deg,pitch_deg\r\n0,0,0\r\n10,-5.5,2.25\r\n");
    put(t, "seeds", "per_eye.csv",
        "t_ms,yaw_deg,pitch_deg,eye\n0,1,1,left\n0,-1,1,right\n5,0,0,both\n9,2,-3,left\n");
    put(t, "regressions", "pixel_1e300.csv", "t_ms,x,y\n0,1e300,5\n1,2,-1e300\n");
    put(t, "regressions", "time_1e308.csv", "t_ms,x,y\n-1.7e308,1,1\n1.7e308,2,2\n");
    put(t, "regressions", "nan_and_inf.csv", "t_ms,x,y\n0,nan,1\n1,inf,2\n");
    put(t, "regressions", "times_go_back.csv", "t_ms,x,y\n5,1,1\n4,2,2\n");
    put(t, "regressions", "header_only.csv", "t_ms,yaw_deg,pitch_deg,eye\n");
    put(t, "regressions", "angle_90.csv", "t_ms,yaw_deg,pitch_deg\n0,90,0\n");
    put(t, "regressions", "unknown_eye.csv", "t_ms,yaw_deg,pitch_deg,eye\n0,1,1,middle\n");
    // Found by fuzzing: per-eye rows out of order across eyes made the trace end before it began.
    put(t, "regressions", "per_eye_interleaved.csv",
        "t_ms,yaw_deg,pitch_deg,eye\n1,1,1,left\n0,-1,1,right\n");
}

// ---- calibration -------------------------------------------------------------------------------

void calibration() {
    using gt::eyetrack::Calibration;
    using gt::eyetrack::CalibrationPoint;
    const std::string t = "calibration";
    const gt::eyetrack::DisplayGeometry display;
    auto fit = [&](int n) {
        std::vector<CalibrationPoint> pts;
        for (int i = 0; i < n; ++i) {
            const double gx = (i % 3) - 1.0, gy = (i / 3) - 1.0;
            const cv::Point2d pupil(160 + 30 * gx + 0.5 * gx * gy, 120 + 25 * gy);
            pts.push_back({pupil, display.pixelAtDeg({14 * gx, -8 * gy + 0.3 * gx * gx})});
        }
        return Calibration::fit(pts, display).toJson().dump(2);
    };
    const std::string poly7 = fit(9);
    put(t, "seeds", "poly7.json", poly7);
    put(t, "seeds", "poly4.json", fit(6));
    nlohmann::json j = nlohmann::json::parse(poly7);
    auto variant = [&](const std::string& name, auto edit) {
        nlohmann::json v = j;
        edit(v);
        put(t, "regressions", name, v.dump());
    };
    // Reported as "version 0" when read through an int.
    variant("version_2pow40.json", [](nlohmann::json& v) { v["version"] = 1LL << 40; });
    variant("scale_1e-300.json", [](nlohmann::json& v) {
        v["pupil_scale"] = std::vector<double>{1e-300, 1e-300};
    });
    variant("coefficient_1e308.json", [](nlohmann::json& v) { v["coefficients_x"][6] = 1e308; });
    variant("display_width_0.json", [](nlohmann::json& v) { v["display"]["width_px"] = 0; });
    variant("mean_is_text.json", [](nlohmann::json& v) { v["pupil_mean"] = "centre"; });
    // Found by fuzzing: a number where the format string belongs escaped as a JSON type_error.
    variant("format_is_number.json", [](nlohmann::json& v) { v["format"] = 1920; });
    // Found by fuzzing (UBSan): nlohmann's get<int>() cast 1.3e123 to int.
    variant("width_px_1.3e123.json", [](nlohmann::json& v) { v["display"]["width_px"] = 1.3e123; });
    variant("points_used_2pow40.json", [](nlohmann::json& v) { v["points_used"] = 1LL << 40; });
    put(t, "regressions", "deep_20000.json", std::string(20000, '[') + std::string(20000, ']'));
    // Version 3: two eyes, one with the 3D model.
    {
        nlohmann::json model3d{
            {"intrinsics", {{"fx", 318.5}, {"fy", 318.5}, {"cx", 159.5}, {"cy", 119.5}}},
            {"rotation", {-1, 0, 0, 0, 1, 0, 0, 0, -1}},
            {"eye_centre_mm", {1.0, -0.5, 30.0}},
            {"eye_radius_mm", 9.0},
            {"pupil_radius_mm", 2.0},
            {"fit_error_deg", 0.5}};
        nlohmann::json v3{{"format", "gazetrace-calibration"},
                          {"version", 3},
                          {"eyes",
                           {{{"eye", "left"}, {"poly", j}, {"model3d", model3d}},
                            {{"eye", "right"}, {"poly", j}}}}};
        put(t, "seeds", "v3_two_eyes.json", v3.dump(2));
        nlohmann::json bad = v3;
        bad["eyes"][0]["model3d"]["rotation"] = {2, 0, 0, 0, 1, 0, 0, 0, 1};
        put(t, "regressions", "v3_not_a_rotation.json", bad.dump());
        bad = v3;
        bad["eyes"][1]["eye"] = "left";
        put(t, "regressions", "v3_same_eye_twice.json", bad.dump());
    }
    put(t, "regressions", "number_1e999.json",
        replaced(poly7, R"("fit_error_deg": )", R"("fit_error_deg": 1e999, "x": )"));
}

// ---- gaze datagrams ----------------------------------------------------------------------------

void datagrams() {
    using namespace gt::eyetrack;
    const std::string t = "datagram";
    const DisplayGeometry display;
    GazeSample s;
    s.tMs = 1234.5;
    s.x = 640.25f;
    s.y = 360.5f;
    s.confidence = 0.875f;
    s.saccade = true;
    s.event = GazeEvent::Saccade;
    // What the emitter writes (one per eye and both), and a third party's minimal ones.
    put(t, "seeds", "emitter_both.json", UdpEmitter::toJson(s, display));
    put(t, "seeds", "emitter_left.json", UdpEmitter::toJson(s, display, "left"));
    nlohmann::json combined = nlohmann::json::parse(UdpEmitter::toJson(s, display));
    combined["vergence_deg"] = 3.5;
    combined["fixation_cm"] = 62.0;
    put(t, "seeds", "emitter_vergence.json", combined.dump());
    put(t, "seeds", "angles_only.json",
        R"({"t_ms":1,"eye":"both","yaw_deg":-20,"pitch_deg":12.5})");
    put(t, "seeds", "pixels_only.json", R"({"x":100,"y":200})");
    put(t, "seeds", "one_eye.json", R"({"eye":"right","yaw_deg":3,"pitch_deg":-2})");
    // Found by a hostile-input run: each ended demo and xr with nlohmann's type_error.
    put(t, "regressions", "saccade_onset_number.json", R"({"x":100,"y":100,"saccade_onset":1})");
    put(t, "regressions", "saccade_onset_string.json",
        R"({"x":100,"y":100,"saccade_onset":"yes"})");
    put(t, "regressions", "saccade_onset_null.json", R"({"x":100,"y":100,"saccade_onset":null})");
    put(t, "regressions", "x_1e400.json", R"({"x":1e400,"y":100})");
    put(t, "regressions", "x_1e300.json", R"({"x":1e300,"y":100})");
    put(t, "regressions", "yaw_90.json", R"({"yaw_deg":90,"pitch_deg":0})");
    put(t, "regressions", "nan_literal.json", R"({"x":NaN,"y":1})");
    put(t, "regressions", "x_without_y.json", R"({"x":100})");
    put(t, "regressions", "no_gaze.json", R"({"t_ms":1,"confidence":1})");
    put(t, "regressions", "eye_number.json", R"({"x":1,"y":1,"eye":7})");
    put(t, "regressions", "screen_huge.json",
        R"({"x":1,"y":1,"screen":[18446744073709551615,-9223372036854775808]})");
    put(t, "regressions", "screen_float.json", R"({"x":1,"y":1,"screen":[1e300,1]})");
    put(t, "regressions", "not_utf8.json", std::string("{\"x\":1,\"y\":2,\"eye\":\"\xff\xfe\"}"));
    put(t, "regressions", "surrogate.json", std::string("{\"eye\":\"\xed\xa0\x80\"}"));
    put(t, "regressions", "empty.json", std::string());
    put(t, "regressions", "array.json", "[1,2,3]");
    put(t, "regressions", "deep_1000.json", std::string(1000, '[') + std::string(1000, ']'));
    put(t, "regressions", "oversized.json",
        R"({"x":1,"y":2,"pad":")" + std::string(4000, 'a') + "\"}");
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: gazetrace_fuzz_corpus OUT_FOLDER\n");
        return 2;
    }
    gOut = argv[1];
    try {
        for (const char* target :
             {"gltf", "radiance", "point_set_cache", "gaze_trace", "calibration", "datagram"})
            fs::remove_all(gOut / target); // only what this program writes
        gltf();
        radiance();
        pointSetCache();
        gazeTrace();
        calibration();
        datagrams();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gazetrace_fuzz_corpus: %s\n", e.what());
        return 1;
    }
    std::printf("gazetrace_fuzz_corpus: wrote %s\n", gOut.c_str());
    return 0;
}
