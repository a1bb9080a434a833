#pragma once
// The glTF 2.0 rules a file MUST follow (glTF 2.0 specification, 3.6 "Binary Data Storage",
// 4.4 "Binary glTF Layout" and 5 "Properties Reference") that tinygltf does not enforce,
// checked on the JSON before tinygltf reads it: tinygltf reads a negative byteOffset as 0, casts
// a 64-bit index to int, drops a 15-number matrix, and checks no accessor, bufferView or sparse
// range against its buffer with arithmetic that cannot wrap. A file that breaks a rule is refused
// with one line naming the file, the field and the rule ("scene.gltf: accessors[3].byteOffset is
// -4, must be >= 0").
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace gt::scene {

// What the loader needs to know about the document beyond what tinygltf keeps.
struct GltfDocumentFacts {
    // Per image: whether a material uses it as a texture the tracers sample (base colour,
    // metallic-roughness, normal, emissive, transmission); the others (occlusion, images no
    // material uses) are not decoded, and count against no budget.
    std::vector<bool> sampledImage;
    // The external files the document names (URIs that are not data: URIs, percent-decoded).
    std::vector<std::string> bufferFiles, imageFiles;
};

// The JSON text of a .gltf, or a GLB's JSON chunk: UTF-8 without a byte-order mark and without
// NUL bytes (glTF 2.0, 3.2 and 4.4.3.2). Throws gt::LoadError naming `file`.
void checkJsonText(std::string_view json, const std::string& file);

// Parses `json` and checks the rules above; throws gt::LoadError naming `file`.
[[nodiscard]] GltfDocumentFacts validateGltfJson(std::string_view json, const std::string& file);

// The parts of a GLB (glTF 2.0, 4.4): where its JSON chunk lies. Throws gt::LoadError naming
// `file` when the header is not a version-2 GLB's or a chunk runs past the file.
struct GlbLayout {
    std::uint64_t jsonOffset = 0, jsonLength = 0;
};
[[nodiscard]] GlbLayout glbLayout(std::string_view bytes, const std::string& file);

// `text` (a parser's message, which quotes what it read) as one line of bounded length: line
// breaks become spaces and a run of more than 120 characters without a space (a data: URI, a
// 5000-digit number, an unterminated string) keeps its first 100 and says how long it was.
[[nodiscard]] std::string messageLine(std::string_view text);

// Animation keys as decoded from a sampler's accessors (glTF 2.0, 3.11 "Animations"). `where`
// names the sampler ("scene.gltf: animation 0 sampler 2"); each check throws gt::LoadError with
// one line "where: what is wrong at which key".
//
// The input: at least one key (two for CUBICSPLINE, whose Hermite segments need two ends), every
// time finite, non-negative and greater than the one before.
void checkSamplerTimes(std::span<const float> times, bool cubic, const std::string& where);
// The output: every value finite and within +-1e12, the loader's limit on coordinates.
void checkSamplerValues(std::span<const float> values, std::size_t components,
                        const std::string& where);
// The output accessor's element count against the keys: `perKey` elements a key (the morph
// target count for weights, else 1), three times that for CUBICSPLINE (in-tangent, value,
// out-tangent).
void checkSamplerCount(std::size_t outputElements, std::size_t keys, std::size_t perKey, bool cubic,
                       const std::string& where);

} // namespace gt::scene
