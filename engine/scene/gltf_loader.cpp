#include "scene/gltf_loader.hpp"

#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string_view>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "checked_size.hpp"
#include "core/error.hpp"
#include "input_file.hpp"
#include "limits.hpp"
#include "scene/animation.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/gltf_validate.hpp"
#include "scene/image_io.hpp"

namespace gt::scene {

namespace {

constexpr uint32_t kMaxTextureSize = 2048; // larger base-colour textures are box-filtered down

// tinygltf quotes the whole URI it failed on: a 100 MB data: URI made a 100 MB error line.
std::string oneLine(const std::string& s) {
    return messageLine(s);
}

struct ImageLoaderState {
    std::vector<std::string>* warnings;
    std::string file;
    const std::vector<bool>* sampledImage; // the images worth decoding
    std::uint64_t maxTextureBytes = 0;
    std::uint64_t decodedBytes = 0; // so far, over all images
};

// Adds an image's decoded size, read from its header, to the file's total before decoding it:
// 400 textures of 2048 x 2048 took 7.5 GB, one at a time each within the per-image limit.
bool withinTextureBudget(ImageLoaderState& state, int index, std::span<const uint8_t> bytes,
                         std::string* err) {
    const auto header = image::headerSize(bytes, "image " + std::to_string(index));
    if (!header) return true; // the decoder says what is wrong with it
    const auto bytesOf = io::checkedMul(std::uint64_t{header->width} * header->height, 4);
    const auto total = bytesOf ? io::checkedAdd(state.decodedBytes, *bytesOf) : std::nullopt;
    if (!total || *total > state.maxTextureBytes) {
        if (err) {
            const std::string reach = total ? std::to_string(*total) + " bytes" : "past 2^64 bytes";
            *err += "decoded textures reach " + reach + " at image " + std::to_string(index) +
                    " (" + std::to_string(header->width) + "x" + std::to_string(header->height) +
                    "), over the limit of " + std::to_string(state.maxTextureBytes) + " bytes (" +
                    io::describeBytes(state.maxTextureBytes) +
                    "; GAZETRACE_MAX_TEXTURE_BYTES raises it)";
        }
        return false;
    }
    state.decodedBytes = *total;
    return true;
}

// Decodes with stb ourselves so that unsupported formats (webp, ktx2) become a warning and a
// missing texture instead of a failed load, while corrupt PNG/JPEG data is still an error.
bool loadImage(tinygltf::Image* image, const int index, std::string* err, std::string* /*warn*/,
               int /*reqW*/, int /*reqH*/, const unsigned char* bytes, int size, void* user) {
    auto* state = static_cast<ImageLoaderState*>(user);
    const auto& used = *state->sampledImage;
    if (index < 0 || static_cast<std::size_t>(index) >= used.size() ||
        !used[static_cast<std::size_t>(index)] || size < 0) {
        // No tracer samples it (gltf_validate.hpp), so it is not decoded.
        image->width = image->height = 0;
        image->image.clear();
        return true;
    }
    const bool png = size >= 8 && std::memcmp(bytes, "\x89PNG", 4) == 0;
    const bool jpeg = size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8;
    if (!png && !jpeg) {
        state->warnings->push_back("image " + std::to_string(index) + " (" + image->mimeType +
                                   ") is not PNG or JPEG; its texture is ignored");
        image->width = image->height = 0;
        image->image.clear();
        return true;
    }
    const std::span encoded(bytes, static_cast<std::size_t>(size));
    try {
        if (!withinTextureBudget(*state, index, encoded, err)) return false;
        const image::DecodedImage d = image::decode(encoded, "image " + std::to_string(index));
        image->width = static_cast<int>(d.width);
        image->height = static_cast<int>(d.height);
        image->component = 4;
        image->bits = 8;
        image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
        image->image = d.rgba;
        return true;
    } catch (const Error& e) {
        if (err) *err += e.what();
        return false;
    }
}

// KHR_texture_transform of a base-colour texture: uv' = T * R * S * uv, with the rotation
// matrix (cos, sin; -sin, cos) that the extension specifies.
struct UvTransform {
    int texCoord = 0; // which TEXCOORD_n the texture reads
    glm::vec2 offset{0.0f}, scale{1.0f};
    float rotation = 0.0f; // radians
    bool operator==(const UvTransform&) const = default;

    void apply(std::vector<float>& uv) const {
        if (offset == glm::vec2(0.0f) && scale == glm::vec2(1.0f) && rotation == 0.0f) {
            return;
        }
        const float c = std::cos(rotation), s = std::sin(rotation);
        for (std::size_t i = 0; i + 1 < uv.size(); i += 2) {
            const float u = scale.x * uv[i], v = scale.y * uv[i + 1];
            uv[i] = c * u + s * v + offset.x;
            uv[i + 1] = -s * u + c * v + offset.y;
        }
    }
};

class Loader {
public:
    Loader(const tinygltf::Model& model, std::string file, GltfLoadReport& report,
           const GltfLoadOptions& options)
        : mModel(model), mFile(std::move(file)), mReport(report), mOptions(options) {}

    // The default scene's nodes, or without a scene list every node no other node names.
    std::vector<int> rootNodes() {
        if (!mModel.scenes.empty()) {
            const int sceneIndex = mModel.defaultScene >= 0 ? mModel.defaultScene : 0;
            if (sceneIndex >= static_cast<int>(mModel.scenes.size()))
                fail("default scene out of range");
            return mModel.scenes[static_cast<std::size_t>(sceneIndex)].nodes;
        }
        std::vector<bool> child(mModel.nodes.size(), false);
        for (const auto& n : mModel.nodes) {
            for (int c : n.children) {
                if (c >= 0 && static_cast<std::size_t>(c) < child.size()) child[c] = true;
            }
        }
        std::vector<int> roots;
        for (std::size_t i = 0; i < mModel.nodes.size(); ++i) {
            if (!child[i]) roots.push_back(static_cast<int>(i));
        }
        return roots;
    }

    Scene load() {
        mScene.name = mFile;
        checkExpansion();
        loadTextures();
        loadMaterials();
        prepareRig();
        for (const int n : rootNodes()) {
            visit(n, glm::mat4(1.0f), 0);
        }
        if (mScene.triangleCount() == 0 && mScene.cages.empty() &&
            (!mRig || mRig->instances.empty()))
            fail("contains no triangle meshes");
        finish();
        if (mRig) {
            mRig->lightNodes.resize(mScene.lights.size(), -1);
            mScene.rig = std::move(mRig);
        }
        return std::move(mScene);
    }

private:
    [[noreturn]] void fail(const std::string& what) const { throw LoadError(mFile + ": " + what); }

    // A factor from the JSON as a float, refused outside [lo, hi]: a colour of 1.7e117 became an
    // infinite light (found by fuzzing). The bounds are wider than the spec's where exporters
    // are known to stray (colours above 1), never wider than a float.
    float factor(double v, double lo, double hi, const std::string& what) const {
        if (!(v >= lo && v <= hi)) {
            char line[160];
            std::snprintf(line, sizeof(line), "%s is %g, outside [%g, %g]", what.c_str(), v, lo,
                          hi);
            fail(line);
        }
        return static_cast<float>(v);
    }

    void loadTextures() {
        mTextureOfImage.assign(mModel.images.size(), -1);
        for (std::size_t i = 0; i < mModel.images.size(); ++i) {
            const tinygltf::Image& img = mModel.images[i];
            if (img.width <= 0 || img.height <= 0 || img.image.empty()) continue;
            if (img.component != 4 || img.bits != 8)
                fail("image " + std::to_string(i) + " is not 8-bit");
            Texture t;
            t.name = img.name.empty() ? img.uri : img.name;
            uint32_t w = static_cast<uint32_t>(img.width), h = static_cast<uint32_t>(img.height);
            std::vector<uint8_t> px(img.image.begin(), img.image.end());
            while (w > kMaxTextureSize || h > kMaxTextureSize) {
                const uint32_t nw = std::max(1u, w / 2), nh = std::max(1u, h / 2);
                std::vector<uint8_t> down(static_cast<std::size_t>(nw) * nh * 4);
                for (uint32_t y = 0; y < nh; ++y) {
                    for (uint32_t x = 0; x < nw; ++x) {
                        for (uint32_t c = 0; c < 4; ++c) {
                            uint32_t sum = 0;
                            for (uint32_t dy = 0; dy < 2; ++dy) {
                                for (uint32_t dx = 0; dx < 2; ++dx) {
                                    const uint32_t sx = std::min(w - 1, 2 * x + dx);
                                    const uint32_t sy = std::min(h - 1, 2 * y + dy);
                                    sum += px[(static_cast<std::size_t>(sy) * w + sx) * 4 + c];
                                }
                            }
                            down[(static_cast<std::size_t>(y) * nw + x) * 4 + c] =
                                static_cast<uint8_t>((sum + 2) / 4);
                        }
                    }
                }
                px = std::move(down);
                w = nw;
                h = nh;
            }
            t.width = w;
            t.height = h;
            t.rgba.resize(static_cast<std::size_t>(w) * h);
            std::memcpy(t.rgba.data(), px.data(), px.size());
            mTextureOfImage[i] = static_cast<int>(mScene.textures.size());
            mScene.textures.push_back(std::move(t));
        }
    }

    int textureFor(int textureIndex) const {
        if (textureIndex < 0) return -1;
        if (static_cast<std::size_t>(textureIndex) >= mModel.textures.size()) {
            fail("texture index " + std::to_string(textureIndex) + " out of range");
        }
        const int source = mModel.textures[textureIndex].source;
        if (source < 0 || static_cast<std::size_t>(source) >= mModel.images.size()) return -1;
        return mTextureOfImage[source];
    }

    // The base-colour texture's UV set and KHR_texture_transform, applied to the UVs as they are
    // read: the tracer then samples with the UVs unchanged.
    template <typename Info> UvTransform uvTransformOf(const Info& info) const {
        UvTransform t;
        t.texCoord = info.texCoord;
        const auto ext = info.extensions.find("KHR_texture_transform");
        if (ext == info.extensions.end() || !ext->second.IsObject()) {
            return t;
        }
        const tinygltf::Value& v = ext->second;
        auto pair = [&](const char* key, glm::vec2& out) {
            if (!v.Has(key)) {
                return;
            }
            const tinygltf::Value& a = v.Get(key);
            if (!a.IsArray() || a.ArrayLen() != 2 || !a.Get(0).IsNumber() || !a.Get(1).IsNumber()) {
                fail(std::string("KHR_texture_transform ") + key + " is not two numbers");
            }
            out = {static_cast<float>(a.Get(0).GetNumberAsDouble()),
                   static_cast<float>(a.Get(1).GetNumberAsDouble())};
        };
        pair("offset", t.offset);
        pair("scale", t.scale);
        if (v.Has("rotation")) {
            if (!v.Get("rotation").IsNumber()) {
                fail("KHR_texture_transform rotation is not a number");
            }
            t.rotation = static_cast<float>(v.Get("rotation").GetNumberAsDouble());
        }
        if (v.Has("texCoord")) {
            if (!v.Get("texCoord").IsInt()) {
                fail("KHR_texture_transform texCoord is not an integer");
            }
            t.texCoord = v.Get("texCoord").GetNumberAsInt();
        }
        if (!std::isfinite(t.offset.x + t.offset.y + t.scale.x + t.scale.y + t.rotation)) {
            fail("KHR_texture_transform has a non-finite value");
        }
        return t;
    }

    // A material's texture other than the base colour's: the tracer reads every texture of a
    // material with the base colour's UVs, so one on other UVs is left out (with a warning).
    template <typename Info>
    int onBaseColourUvs(const Info& info, const std::string& material, const char* what) {
        const int t = textureFor(info.index);
        if (t < 0 || uvTransformOf(info) == mMaterialUv.back()) {
            return t;
        }
        mReport.warnings.push_back("material '" + material + "': " + what +
                                   " texture on other UVs than the base colour's, left out");
        return -1;
    }

    // KHR_materials_transmission (factor, texture's R) and KHR_materials_ior.
    void loadTransmission(const tinygltf::Material& m, const std::string& name, Material& out) {
        const auto tr = m.extensions.find("KHR_materials_transmission");
        if (tr != m.extensions.end() && tr->second.IsObject()) {
            const tinygltf::Value& v = tr->second;
            if (v.Has("transmissionFactor")) {
                out.transmission =
                    static_cast<float>(factor(v.Get("transmissionFactor").GetNumberAsDouble(), 0.0,
                                              1.0, name + " transmissionFactor"));
            }
            if (v.Has("transmissionTexture") && v.Get("transmissionTexture").Has("index")) {
                tinygltf::TextureInfo info;
                info.index = v.Get("transmissionTexture").Get("index").GetNumberAsInt();
                if (v.Get("transmissionTexture").Has("texCoord")) {
                    info.texCoord = v.Get("transmissionTexture").Get("texCoord").GetNumberAsInt();
                }
                out.transmissionTexture = onBaseColourUvs(info, m.name, "transmission");
            }
        }
        const auto ior = m.extensions.find("KHR_materials_ior");
        if (ior != m.extensions.end() && ior->second.Has("ior")) {
            // KHR_materials_ior: 1 or anything from 1 up (1 stands for no Fresnel reflection).
            out.ior = static_cast<float>(
                factor(ior->second.Get("ior").GetNumberAsDouble(), 1.0, 100.0, name + " ior"));
        }
    }

    void loadMaterials() {
        std::string translucent;
        for (const tinygltf::Material& m : mModel.materials) {
            Material out;
            out.name = m.name;
            const auto& pbr = m.pbrMetallicRoughness;
            const std::string name = "material '" + m.name + "'";
            if (pbr.baseColorFactor.size() == 4) {
                for (int c = 0; c < 4; ++c) {
                    out.baseColor[c] = factor(pbr.baseColorFactor[static_cast<std::size_t>(c)], 0.0,
                                              1e6, name + " baseColorFactor");
                }
            }
            out.baseColorTexture = textureFor(pbr.baseColorTexture.index);
            mMaterialUv.push_back(uvTransformOf(pbr.baseColorTexture));
            if (pbr.baseColorTexture.index >= 0 && out.baseColorTexture < 0) {
                mReport.warnings.push_back(
                    "material '" + m.name +
                    "': base-colour texture not available, using the factor");
            }
            out.metallicRoughnessTexture =
                onBaseColourUvs(pbr.metallicRoughnessTexture, m.name, "metallic-roughness");
            out.normalTexture = onBaseColourUvs(m.normalTexture, m.name, "normal");
            out.normalScale = static_cast<float>(m.normalTexture.scale);
            if (!std::isfinite(out.normalScale)) {
                fail(name + " normalTexture scale is not finite");
            }
            out.emissiveTexture = onBaseColourUvs(m.emissiveTexture, m.name, "emissive");
            loadTransmission(m, name, out);
            out.metallic = static_cast<float>(std::clamp(pbr.metallicFactor, 0.0, 1.0));
            out.roughness = static_cast<float>(std::clamp(pbr.roughnessFactor, 0.0, 1.0));
            if (m.emissiveFactor.size() == 3) {
                for (int c = 0; c < 3; ++c) {
                    out.emissive[c] = factor(m.emissiveFactor[static_cast<std::size_t>(c)], 0.0,
                                             1e6, name + " emissiveFactor");
                }
            }
            auto strength = m.extensions.find("KHR_materials_emissive_strength");
            if (strength != m.extensions.end() && strength->second.Has("emissiveStrength")) {
                out.emissive *= factor(strength->second.Get("emissiveStrength").GetNumberAsDouble(),
                                       0.0, 1e6, name + " emissiveStrength");
            }
            out.unlit = m.extensions.count("KHR_materials_unlit") > 0;
            if (m.alphaMode == "MASK") {
                out.alphaCutoff = factor(m.alphaCutoff, 0.0, 1e6, name + " alphaCutoff");
            } else if (m.alphaMode == "BLEND") {
                out.alphaBlend = true;
                translucent += (translucent.empty() ? "" : ", ") + ("'" + m.name + "'");
            }
            mScene.materials.push_back(out);
        }
        if (!translucent.empty()) {
            // The direct integrator has no transparency; say so rather than look right.
            mReport.warnings.push_back("material(s) " + translucent +
                                       " use alphaMode BLEND; rendered opaque (but by "
                                       "--integrator path)");
        }
        mDefaultMaterial = static_cast<uint32_t>(mScene.materials.size());
        mMaterialUv.emplace_back();
        Material grey;
        grey.baseColor = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
        grey.name = "default";
        mScene.materials.push_back(grey);
    }

    // Reads `count` elements of an accessor as floats.
    std::vector<float> readFloats(int accessorIndex, int components) const {
        const tinygltf::Accessor& a = accessor(accessorIndex);
        const int n = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
        if (n != components) {
            fail("accessor " + std::to_string(accessorIndex) + " has " + std::to_string(n) +
                 " components, expected " + std::to_string(components));
        }
        const auto [data, stride] = span(a, accessorIndex);
        std::vector<float> out(elements(a.count, static_cast<std::uint64_t>(n), accessorIndex));
        for (std::size_t i = 0; i < a.count; ++i) {
            const unsigned char* e = data + i * stride;
            for (int c = 0; c < n; ++c) {
                float v = 0.0f;
                switch (a.componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT:
                    std::memcpy(&v, e + 4 * static_cast<std::size_t>(c), 4);
                    break;
                // Integers (core colours and UVs, KHR_mesh_quantization) are read as they are
                // stored or, when normalised, mapped to [0, 1] / [-1, 1] (glTF 2.0, 3.11).
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                    v = a.normalized ? e[c] / 255.0f : static_cast<float>(e[c]);
                    break;
                case TINYGLTF_COMPONENT_TYPE_BYTE: {
                    int8_t b;
                    std::memcpy(&b, e + c, 1);
                    v = a.normalized ? std::max(b / 127.0f, -1.0f) : static_cast<float>(b);
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                    uint16_t u;
                    std::memcpy(&u, e + 2 * static_cast<std::size_t>(c), 2);
                    v = a.normalized ? u / 65535.0f : static_cast<float>(u);
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_SHORT: {
                    int16_t h;
                    std::memcpy(&h, e + 2 * static_cast<std::size_t>(c), 2);
                    v = a.normalized ? std::max(h / 32767.0f, -1.0f) : static_cast<float>(h);
                    break;
                }
                default:
                    fail("accessor " + std::to_string(accessorIndex) +
                         " has an unsupported component type " + std::to_string(a.componentType));
                }
                out[i * n + c] = v;
            }
        }
        return out;
    }

    std::vector<uint32_t> readIndices(int accessorIndex) const {
        const tinygltf::Accessor& a = accessor(accessorIndex);
        if (a.type != TINYGLTF_TYPE_SCALAR) fail("index accessor is not scalar");
        const auto [data, stride] = span(a, accessorIndex);
        std::vector<uint32_t> out(elements(a.count, 1, accessorIndex));
        for (std::size_t i = 0; i < a.count; ++i) {
            const unsigned char* e = data + i * stride;
            switch (a.componentType) {
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                out[i] = e[0];
                break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                uint16_t s;
                std::memcpy(&s, e, 2);
                out[i] = s;
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
                std::memcpy(&out[i], e, 4);
                break;
            default:
                fail("index accessor has an unsupported component type");
            }
        }
        return out;
    }

    // count x components, refused when the product wraps around: a count of 2^64 / 3 + 1 made
    // a 2-float vector that the loop then wrote count elements into.
    std::size_t elements(std::uint64_t count, std::uint64_t components, int index) const {
        const auto n = io::checkedMul(count, components);
        if (!n || *n > std::numeric_limits<std::size_t>::max() / sizeof(float)) {
            fail("accessor " + std::to_string(index) + " count " + std::to_string(count) +
                 " is too large to hold");
        }
        return static_cast<std::size_t>(*n);
    }

    const tinygltf::Accessor& accessor(int index) const {
        if (index < 0 || static_cast<std::size_t>(index) >= mModel.accessors.size()) {
            fail("accessor index " + std::to_string(index) + " out of range");
        }
        return mModel.accessors[index];
    }

    // Start pointer and stride of an accessor, after checking it lies inside its buffer.
    std::pair<const unsigned char*, std::size_t> span(const tinygltf::Accessor& a,
                                                      int index) const {
        if (a.sparse.isSparse || a.bufferView < 0) {
            return dense(a, index);
        }
        const std::string where = "accessor " + std::to_string(index);
        const auto bytes = viewBytes(a.bufferView, where);
        const std::size_t size = elementSize(a, index);
        const std::size_t stride = mModel.bufferViews[a.bufferView].byteStride
                                       ? mModel.bufferViews[a.bufferView].byteStride
                                       : size;
        // Checked without wrap-around: count x stride of 2^64 + 8 passed as 8 bytes.
        const auto extent = io::stridedSpan(a.count, stride, size);
        if (!extent || !io::rangeFits(a.byteOffset, *extent, bytes.size())) {
            fail(where + " runs past the end of bufferView " + std::to_string(a.bufferView));
        }
        return {bytes.data() + a.byteOffset, stride};
    }

    // Bytes of a buffer view, checked against its buffer.
    std::span<const unsigned char> viewBytes(int viewIndex, const std::string& where) const {
        if (viewIndex < 0 || static_cast<std::size_t>(viewIndex) >= mModel.bufferViews.size()) {
            fail(where + " has no valid bufferView");
        }
        const tinygltf::BufferView& view = mModel.bufferViews[viewIndex];
        if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= mModel.buffers.size()) {
            fail(where + ": bufferView " + std::to_string(viewIndex) + " has no valid buffer");
        }
        const tinygltf::Buffer& buffer = mModel.buffers[view.buffer];
        if (!io::rangeFits(view.byteOffset, view.byteLength, buffer.data.size())) {
            fail("bufferView " + std::to_string(viewIndex) + " runs past the end of buffer " +
                 std::to_string(view.buffer) + " (" + std::to_string(buffer.data.size()) +
                 " bytes; truncated or missing file?)");
        }
        return {buffer.data.data() + view.byteOffset, view.byteLength};
    }

    // An accessor with no bufferView (zeros) or with sparse substitutions (glTF 2.0, 3.6.2.3),
    // made dense once and kept for the loader's lifetime.
    std::pair<const unsigned char*, std::size_t> dense(const tinygltf::Accessor& a,
                                                       int index) const {
        if (const auto it = mDense.find(index); it != mDense.end()) {
            return {it->second.data(), elementSize(a, index)};
        }
        const std::string where = "accessor " + std::to_string(index);
        const std::size_t size = elementSize(a, index);
        // Nothing bounds a count that no bufferView backs: refuse what no real mesh needs
        // rather than fail to allocate it. Three vertices per triangle of the limit is all a
        // scene can use (178,956,969 zeros took 4.2 GB before "no triangles").
        constexpr std::size_t kMaxDenseBytes = std::size_t{1} << 31;
        const double limit = mOptions.maxTriangles;
        if (a.count > kMaxDenseBytes / size || static_cast<double>(a.count) > 3.0 * limit) {
            char what[200];
            std::snprintf(what, sizeof(what),
                          " has %zu elements, more than 3 x the limit of %.3g triangles can use",
                          a.count, limit);
            fail(where + what);
        }
        std::vector<unsigned char> out(a.count * size, 0); // bounded just above
        if (a.bufferView >= 0) {
            tinygltf::Accessor base = a;
            base.sparse.isSparse = false;
            const auto [data, stride] = span(base, index);
            for (std::size_t i = 0; i < a.count; ++i) {
                std::memcpy(out.data() + i * size, data + i * stride, size);
            }
        }
        if (a.sparse.isSparse) {
            const auto& sp = a.sparse;
            const std::size_t count = static_cast<std::size_t>(std::max(sp.count, 0));
            if (sp.count < 1 || count > a.count) fail(where + ": bad sparse count");
            const int idxSize =
                tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(sp.indices.componentType));
            if (idxSize != 1 && idxSize != 2 && idxSize != 4) {
                fail(where + ": sparse indices have an invalid component type");
            }
            const auto idx = viewBytes(sp.indices.bufferView, where + " sparse indices");
            const auto val = viewBytes(sp.values.bufferView, where + " sparse values");
            const auto idxOffset = io::nonNegative(sp.indices.byteOffset);
            const auto valOffset = io::nonNegative(sp.values.byteOffset);
            const auto idxBytes = io::checkedMul(count, static_cast<std::uint64_t>(idxSize));
            const auto valBytes = io::checkedMul(count, size);
            if (!idxOffset || !valOffset || !idxBytes || !valBytes ||
                !io::rangeFits(*idxOffset, *idxBytes, idx.size()) ||
                !io::rangeFits(*valOffset, *valBytes, val.size())) {
                fail(where + ": sparse data runs past the end of its bufferView");
            }
            for (std::size_t i = 0; i < count; ++i) {
                uint32_t target = 0;
                std::memcpy(&target, idx.data() + *idxOffset + i * idxSize, idxSize); // little end
                if (target >= a.count) {
                    fail(where + ": sparse index " + std::to_string(target) + " out of range");
                }
                std::memcpy(out.data() + target * size, val.data() + *valOffset + i * size, size);
            }
        }
        const auto& stored = mDense.emplace(index, std::move(out)).first->second;
        return {stored.data(), size};
    }

    std::size_t elementSize(const tinygltf::Accessor& a, int index) const {
        const int compSize =
            tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
        const int comps = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
        if (compSize <= 0 || comps <= 0) {
            fail("accessor " + std::to_string(index) + " has an invalid type");
        }
        return static_cast<std::size_t>(compSize) * static_cast<std::size_t>(comps);
    }

    glm::mat4 localMatrix(const tinygltf::Node& n) const {
        if (n.matrix.size() == 16) {
            glm::mat4 m;
            for (int i = 0; i < 16; ++i)
                glm::value_ptr(m)[i] = static_cast<float>(n.matrix[i]);
            return m;
        }
        glm::mat4 m(1.0f);
        if (n.translation.size() == 3) {
            m = glm::translate(m, glm::vec3(n.translation[0], n.translation[1], n.translation[2]));
        }
        if (n.rotation.size() == 4) {
            const glm::quat q(static_cast<float>(n.rotation[3]), static_cast<float>(n.rotation[0]),
                              static_cast<float>(n.rotation[1]), static_cast<float>(n.rotation[2]));
            m = m * glm::mat4_cast(q);
        }
        if (n.scale.size() == 3) m = glm::scale(m, glm::vec3(n.scale[0], n.scale[1], n.scale[2]));
        return m;
    }

    // Triangles the scene's node graph expands to, counted before anything is built: a node
    // graph whose levels each reference the next twice expands to 2^24 instances from 25 nodes
    // (it ran out of memory after 135 s), and one mesh may be referenced by thousands of
    // primitives and nodes. Counted per node once (memoised: the graph may be a DAG), with
    // saturation instead of overflow.

    double primitiveTriangles(const tinygltf::Primitive& prim) const {
        if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
            prim.mode != TINYGLTF_MODE_TRIANGLE_FAN && prim.mode != -1) {
            return 0.0;
        }
        int accessor = prim.indices;
        if (accessor < 0) {
            const auto it = prim.attributes.find("POSITION");
            if (it == prim.attributes.end()) return 0.0;
            accessor = it->second;
        }
        if (accessor < 0 || static_cast<std::size_t>(accessor) >= mModel.accessors.size()) {
            return 0.0; // reported where it is used
        }
        const double n = static_cast<double>(mModel.accessors[accessor].count);
        return prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP || prim.mode == TINYGLTF_MODE_TRIANGLE_FAN
                   ? std::max(0.0, n - 2.0)
                   : std::floor(n / 3.0);
    }

    // Counted before anything is expanded: the triangles the node graph instantiates, and the
    // node instances it visits. Both are needed: a graph of meshless nodes, each referencing the
    // next twice, 24 deep, is 2^24 visits and no triangle (found by fuzzing: 11 s per file).
    void checkExpansion() {
        std::vector<double> meshTriangles(mModel.meshes.size(), 0.0);
        for (std::size_t m = 0; m < mModel.meshes.size(); ++m) {
            for (const tinygltf::Primitive& prim : mModel.meshes[m].primitives) {
                meshTriangles[m] += primitiveTriangles(prim);
            }
            // A cage is refined up to kLodRefinements[0] times: 4^3 quads per quad, 3 x 4^2
            // per triangle, two triangles each.
            if (isCage(mModel.meshes[m])) meshTriangles[m] *= 128.0;
        }
        struct Expansion {
            double triangles = -1.0; // -1: not counted yet
            double instances = 0.0;
        };
        std::vector<Expansion> memo(mModel.nodes.size());
        std::vector<char> onPath(mModel.nodes.size(), 0);
        // Iterative-enough: depth is bounded like visit()'s (256).
        std::function<Expansion(int, int)> count = [&](int node, int depth) -> Expansion {
            if (node < 0 || static_cast<std::size_t>(node) >= mModel.nodes.size() || depth > 256 ||
                onPath[static_cast<std::size_t>(node)]) {
                return {0.0, 0.0}; // out of range or a cycle: visit() reports them
            }
            Expansion& m = memo[static_cast<std::size_t>(node)];
            if (m.triangles >= 0.0) return m;
            onPath[static_cast<std::size_t>(node)] = 1;
            const tinygltf::Node& n = mModel.nodes[static_cast<std::size_t>(node)];
            Expansion total{n.mesh >= 0 && static_cast<std::size_t>(n.mesh) < meshTriangles.size()
                                ? meshTriangles[static_cast<std::size_t>(n.mesh)]
                                : 0.0,
                            1.0};
            for (const int c : n.children) {
                const Expansion child = count(c, depth + 1);
                total.triangles = std::min(total.triangles + child.triangles, 1e300);
                total.instances = std::min(total.instances + child.instances, 1e300);
            }
            onPath[static_cast<std::size_t>(node)] = 0;
            return m = total;
        };
        Expansion total{0.0, 0.0};
        for (const int n : rootNodes()) {
            const Expansion e = count(n, 0);
            total.triangles += e.triangles;
            total.instances += e.instances;
        }
        const auto refuse = [&](double value, const char* what, double limit) {
            char line[200];
            std::snprintf(line, sizeof(line),
                          "its nodes expand to %.3g %s, above the limit of %.3g", value, what,
                          limit);
            fail(line);
        };
        if (total.triangles > mOptions.maxTriangles) {
            refuse(total.triangles, "triangles", mOptions.maxTriangles);
        }
        if (total.instances > mOptions.maxInstances) {
            refuse(total.instances, "node instances", mOptions.maxInstances);
        }
    }

    // The camera looks down its node's -Z with +Y up. Normalised in double: a scale of 1e30 made
    // the float length overflow to infinity and both axes zero. A scale of 0 or a singular matrix
    // on the node or a parent leaves no direction at all: normalize gave NaN axes and a flat
    // image that still "rendered", so it is refused naming the node.
    void placeCameraAxes(const glm::mat4& world, int nodeIndex) {
        const glm::dvec3 forward(glm::dmat4(world) * glm::dvec4(0, 0, -1, 0));
        const glm::dvec3 up(glm::dmat4(world) * glm::dvec4(0, 1, 0, 0));
        const double across = glm::length(glm::cross(forward, up));
        if (!(across > 1e-12 * glm::length(forward) * glm::length(up)) || !std::isfinite(across)) {
            fail("nodes[" + std::to_string(nodeIndex) +
                 "] holds the camera, but its world transform leaves the camera no view "
                 "direction (a scale of 0 or a singular matrix)");
        }
        mScene.camera.forward = glm::vec3(glm::normalize(forward));
        mScene.camera.up = glm::vec3(glm::normalize(up));
    }

    void visit(int nodeIndex, const glm::mat4& parent, int depth) {
        if (nodeIndex < 0 || static_cast<std::size_t>(nodeIndex) >= mModel.nodes.size()) {
            fail("node index " + std::to_string(nodeIndex) + " out of range");
        }
        if (depth > 256) fail("node hierarchy deeper than 256 (a cycle?)");
        const tinygltf::Node& node = mModel.nodes[nodeIndex];
        const glm::mat4 world = parent * localMatrix(node);
        if (node.mesh >= 0) {
            if (static_cast<std::size_t>(node.mesh) >= mModel.meshes.size()) {
                fail("node " + std::to_string(nodeIndex) + " has mesh index out of range");
            }
            if (rigBound(nodeIndex, mModel.meshes[node.mesh])) {
                addRigInstance(nodeIndex);
            } else {
                addMesh(mModel.meshes[node.mesh], world, nodeIndex);
            }
        }
        if (node.camera >= 0 && !mHaveCamera &&
            static_cast<std::size_t>(node.camera) < mModel.cameras.size()) {
            const tinygltf::Camera& c = mModel.cameras[node.camera];
            mScene.camera.position = glm::vec3(world[3]);
            placeCameraAxes(world, nodeIndex);
            if (c.type == "perspective" && c.perspective.yfov > 0.0) {
                mScene.camera.yfov = factor(c.perspective.yfov, 1e-6, 3.14159,
                                            "camera " + std::to_string(node.camera) + " yfov");
            }
            mHaveCamera = true;
            if (moves(nodeIndex))
                mRig->cameraNode = mRigNodeOf[static_cast<std::size_t>(nodeIndex)];
        }
        auto light = node.extensions.find("KHR_lights_punctual");
        if (light != node.extensions.end() && light->second.Has("light")) {
            // IsInt first: tinygltf's GetNumberAsInt casts any real to int, and 1.5e44 is
            // undefined behaviour there (found by fuzzing under UBSan).
            const tinygltf::Value& ref = light->second.Get("light");
            const int li = ref.IsInt() ? ref.GetNumberAsInt() : -1;
            if (li < 0 || static_cast<std::size_t>(li) >= mModel.lights.size()) {
                fail("node " + std::to_string(nodeIndex) + " references light " +
                     (ref.IsInt() ? std::to_string(li) : std::string("that is not an index")) +
                     ", which does not exist");
            }
            addLight(mModel.lights[li], li, world);
            if (mRig) {
                mRig->lightNodes.resize(mScene.lights.size() - 1, -1);
                mRig->lightNodes.push_back(
                    moves(nodeIndex) ? mRigNodeOf[static_cast<std::size_t>(nodeIndex)] : -1);
            }
        }
        for (int c : node.children)
            visit(c, world, depth + 1);
    }

    void addLight(const tinygltf::Light& l, int index, const glm::mat4& world) {
        const std::string name = "light " + std::to_string(index);
        Light out;
        if (l.type == "directional")
            out.type = LightType::Directional;
        else if (l.type == "spot")
            out.type = LightType::Spot;
        else if (l.type == "point")
            out.type = LightType::Point;
        else
            fail("light type '" + l.type + "' is not point, spot or directional");
        out.position = glm::vec3(world[3]);
        out.direction = glm::normalize(glm::vec3(world * glm::vec4(0, 0, -1, 0)));
        // A rotation of 1e30 overflows the node's matrix: the light would point nowhere.
        if (!std::isfinite(out.direction.x + out.direction.y + out.direction.z + out.position.x +
                           out.position.y + out.position.z)) {
            fail(name + ": its node's transform leaves it no finite position and direction");
        }
        if (l.color.size() == 3) {
            for (int c = 0; c < 3; ++c) {
                out.color[c] =
                    factor(l.color[static_cast<std::size_t>(c)], 0.0, 1e6, name + " color");
            }
        }
        // Candela or lux: the sun is 1e5 lux; 1e12 leaves room without reaching a float's end.
        out.intensity = factor(l.intensity, 0.0, 1e12, name + " intensity");
        out.range = factor(l.range, 0.0, 1e12, name + " range");
        const double quarter = 1.5707964; // pi / 2, the spec's largest cone angle (rounded up)
        out.innerConeCos = static_cast<float>(
            std::cos(factor(l.spot.innerConeAngle, 0.0, quarter, name + " innerConeAngle")));
        out.outerConeCos = static_cast<float>(
            std::cos(factor(l.spot.outerConeAngle, 0.0, quarter, name + " outerConeAngle")));
        mScene.lights.push_back(out);
    }

    // World-space coordinates beyond this are refused: no real scene needs them (1e12 m is
    // seven times the Earth-Sun distance), and past about 1e19 the BVH's centroid sums and box
    // areas overflow a float (a node at 3.4e38 crashed the build).
    static constexpr float kMaxCoordinate = 1e12f;

    // A NaN or infinite texture coordinate (in the buffer, or made by a texture transform that
    // carries a huge one past the float range) samples nothing: refused, as a position is.
    void checkTexCoords(const std::vector<float>& uv, const std::string& mesh,
                        const std::string& set) const {
        for (std::size_t i = 0; i < uv.size(); ++i) {
            if (!std::isfinite(uv[i])) {
                fail("mesh '" + mesh + "': " + set + " of vertex " + std::to_string(i / 2) +
                     " is not a finite number (NaN or infinity, after any texture transform)");
            }
        }
    }

    void checkWorldPosition(const glm::vec3& w, int nodeIndex) {
        if (std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z) &&
            std::abs(w.x) <= kMaxCoordinate && std::abs(w.y) <= kMaxCoordinate &&
            std::abs(w.z) <= kMaxCoordinate) {
            return;
        }
        const std::string& name = mModel.nodes[static_cast<std::size_t>(nodeIndex)].name;
        char where[96];
        std::snprintf(where, sizeof(where), "(%g, %g, %g)", w.x, w.y, w.z);
        fail("node " + std::to_string(nodeIndex) + (name.empty() ? "" : " '" + name + "'") +
             " puts a vertex at " + where +
             ", outside the +-1e12 units a scene may span (check its translation and scale)");
    }

    // gazetrace's glTF convention for subdivision surfaces (README, "Geometric LOD"): a mesh
    // whose extras hold "gazetrace_subdivision": "catmull-clark" is a Catmull-Clark control cage;
    // its triangles (welded by position) are the cage's faces, or, with "gazetrace_quads": true,
    // each pair of consecutive triangles (a, b, c), (a, c, d) is the quad (a, b, c, d), as
    // exporters triangulate quads.
    bool isCage(const tinygltf::Mesh& mesh) const {
        if (!mesh.extras.IsObject() || !mesh.extras.Has("gazetrace_subdivision")) return false;
        const tinygltf::Value& v = mesh.extras.Get("gazetrace_subdivision");
        if (!v.IsString() || v.Get<std::string>() != "catmull-clark") {
            fail("mesh '" + mesh.name +
                 "': extras.gazetrace_subdivision must be \"catmull-clark\"");
        }
        return true;
    }
    static bool quadPairs(const tinygltf::Mesh& mesh) {
        if (!mesh.extras.IsObject() || !mesh.extras.Has("gazetrace_quads")) return false;
        const tinygltf::Value& v = mesh.extras.Get("gazetrace_quads");
        return v.IsBool() && v.Get<bool>();
    }

    void addCage(const tinygltf::Mesh& mesh, const std::vector<glm::vec3>& corners,
                 uint32_t material) {
        SubdivisionCage cage;
        cage.name = mesh.name.empty() ? "cage" : mesh.name;
        cage.material = material;
        std::map<std::tuple<float, float, float>, uint32_t> weld;
        auto index = [&](const glm::vec3& p) {
            const auto [it, added] =
                weld.emplace(std::tuple{p.x, p.y, p.z}, static_cast<uint32_t>(cage.points.size()));
            if (added) cage.points.push_back(p);
            return it->second;
        };
        const bool quads = quadPairs(mesh);
        for (std::size_t t = 0; t + 2 < corners.size(); t += 3) {
            std::vector<uint32_t> face{index(corners[t]), index(corners[t + 1]),
                                       index(corners[t + 2])};
            if (quads && t + 5 < corners.size()) {
                const uint32_t a = index(corners[t + 3]), c = index(corners[t + 4]),
                               d = index(corners[t + 5]);
                if (a == face[0] && c == face[2]) {
                    face.push_back(d);
                    t += 3;
                }
            }
            std::vector<uint32_t> sorted = face;
            std::sort(sorted.begin(), sorted.end());
            if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) continue;
            cage.faceSizes.push_back(static_cast<uint32_t>(face.size()));
            cage.indices.insert(cage.indices.end(), face.begin(), face.end());
        }
        if (!cage.faceSizes.empty()) mScene.cages.push_back(std::move(cage));
    }

    // A triangle primitive's attributes and its triangles as indices into them (strips and fans
    // converted), read the same way for static and animated meshes.
    struct PrimitiveData {
        std::vector<float> p, n, uv;
        std::vector<uint32_t> tris;
        uint32_t material = 0;
        std::size_t vertexCount = 0;
    };

    // Whether `prim` is drawn as triangles; a points or lines primitive is skipped with a warning.
    bool trianglePrimitive(const tinygltf::Mesh& mesh, const tinygltf::Primitive& prim) {
        if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
            prim.mode != TINYGLTF_MODE_TRIANGLE_FAN && prim.mode != -1) {
            mReport.warnings.push_back("mesh '" + mesh.name + "': skipped a primitive of mode " +
                                       std::to_string(prim.mode) + " (points or lines)");
            return false;
        }
        return true;
    }

    PrimitiveData readPrimitive(const tinygltf::Mesh& mesh, const tinygltf::Primitive& prim) const {
        PrimitiveData d;
        auto pos = prim.attributes.find("POSITION");
        if (pos == prim.attributes.end())
            fail("mesh '" + mesh.name + "' has a primitive without POSITION");
        d.p = readFloats(pos->second, 3);
        const std::size_t vertexCount = d.p.size() / 3;
        d.vertexCount = vertexCount;
        if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
            d.n = readFloats(it->second, 3);
            if (d.n.size() != d.p.size())
                fail("mesh '" + mesh.name + "': NORMAL count differs from POSITION");
        }
        d.material = mDefaultMaterial;
        if (prim.material >= 0) {
            if (static_cast<std::size_t>(prim.material) >= mModel.materials.size()) {
                fail("mesh '" + mesh.name + "' uses material " + std::to_string(prim.material) +
                     ", which does not exist");
            }
            d.material = static_cast<uint32_t>(prim.material);
        }
        const UvTransform& uvt = mMaterialUv[d.material];
        const std::string uvSet = "TEXCOORD_" + std::to_string(uvt.texCoord);
        if (auto it = prim.attributes.find(uvSet); it != prim.attributes.end()) {
            d.uv = readFloats(it->second, 2);
            if (d.uv.size() / 2 != vertexCount)
                fail("mesh '" + mesh.name + "': " + uvSet + " count differs from POSITION");
            uvt.apply(d.uv);
            checkTexCoords(d.uv, mesh.name, uvSet);
        }
        d.tris = triangleIndices(mesh, prim, vertexCount);
        return d;
    }

    std::vector<uint32_t> triangleIndices(const tinygltf::Mesh& mesh,
                                          const tinygltf::Primitive& prim,
                                          std::size_t vertexCount) const {
        std::vector<uint32_t> idx;
        if (prim.indices >= 0) {
            idx = readIndices(prim.indices);
        } else {
            idx.resize(vertexCount);
            for (uint32_t i = 0; i < vertexCount; ++i)
                idx[i] = i;
        }
        for (uint32_t i : idx) {
            if (i >= vertexCount)
                fail("mesh '" + mesh.name + "': index " + std::to_string(i) + " out of range");
        }
        std::vector<uint32_t> tris;
        if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            for (std::size_t i = 2; i < idx.size(); ++i) {
                if (i % 2 == 0)
                    tris.insert(tris.end(), {idx[i - 2], idx[i - 1], idx[i]});
                else
                    tris.insert(tris.end(), {idx[i - 1], idx[i - 2], idx[i]});
            }
        } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
            for (std::size_t i = 2; i < idx.size(); ++i)
                tris.insert(tris.end(), {idx[0], idx[i - 1], idx[i]});
        } else {
            tris = std::move(idx);
            tris.resize(tris.size() / 3 * 3);
        }
        return tris;
    }

    // One corner of a triangle: position through `toSpace`, normal through `normalMatrix`.
    static Vertex corner(const PrimitiveData& d, uint32_t i, const glm::mat4& toSpace,
                         const glm::mat3& normalMatrix) {
        Vertex v{};
        const std::vector<float>& p = d.p;
        v.position = glm::vec3(toSpace * glm::vec4(p[3 * i], p[3 * i + 1], p[3 * i + 2], 1.0f));
        v.uv = d.uv.empty() ? glm::vec2(0.0f) : glm::vec2(d.uv[2 * i], d.uv[2 * i + 1]);
        if (!d.n.empty())
            v.normal = normalMatrix * glm::vec3(d.n[3 * i], d.n[3 * i + 1], d.n[3 * i + 2]);
        return v;
    }

    // The triangle's face normal where the file gives no usable normal; false for a degenerate
    // triangle, which is dropped.
    static bool finishNormals(Vertex (&v)[3], bool fileNormals) {
        const glm::vec3 face =
            glm::cross(v[1].position - v[0].position, v[2].position - v[0].position);
        if (glm::dot(face, face) <= 0.0f || !std::isfinite(face.x + face.y + face.z))
            return false; // degenerate
        const glm::vec3 fn = glm::normalize(face);
        for (Vertex& x : v) {
            const float len = glm::length(x.normal);
            x.normal =
                (!fileNormals || !(len > 1e-12f) || !std::isfinite(len)) ? fn : x.normal / len;
        }
        return true;
    }

    void addMesh(const tinygltf::Mesh& mesh, const glm::mat4& world, int nodeIndex) {
        const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(world)));
        const bool cage = isCage(mesh);
        for (const tinygltf::Primitive& prim : mesh.primitives) {
            if (!trianglePrimitive(mesh, prim)) continue;
            const PrimitiveData d = readPrimitive(mesh, prim);
            const std::vector<float>& p = d.p;
            const std::vector<uint32_t>& tris = d.tris;
            if (cage) {
                std::vector<glm::vec3> corners;
                for (const uint32_t i : tris) {
                    corners.emplace_back(world *
                                         glm::vec4(p[3 * i], p[3 * i + 1], p[3 * i + 2], 1.0f));
                    checkWorldPosition(corners.back(), nodeIndex);
                }
                addCage(mesh, corners, d.material);
                continue;
            }
            for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
                Vertex v[3];
                for (int k = 0; k < 3; ++k) {
                    v[k] = corner(d, tris[t + k], world, normalMatrix);
                    checkWorldPosition(v[k].position, nodeIndex);
                }
                if (!finishNormals(v, !d.n.empty())) continue;
                mScene.vertices.insert(mScene.vertices.end(), {v[0], v[1], v[2]});
                mScene.triangleMaterial.push_back(d.material);
            }
        }
    }

    // Scenes that move (animation.hpp). A rig is built only when the file animates, skins or
    // morphs something: a file with none of them loads exactly as it did without one.

    static std::size_t morphTargetCountOf(const tinygltf::Mesh& mesh) {
        return mesh.primitives.empty() ? 0 : mesh.primitives.front().targets.size();
    }

    bool needsRig() const {
        if (!mModel.animations.empty() || !mModel.skins.empty()) return true;
        return std::any_of(mModel.meshes.begin(), mModel.meshes.end(), [](const tinygltf::Mesh& m) {
            return std::any_of(m.primitives.begin(), m.primitives.end(),
                               [](const tinygltf::Primitive& p) { return !p.targets.empty(); });
        });
    }

    void prepareRig() {
        if (!needsRig()) return;
        mRig = std::make_shared<Rig>();
        mRigMeshOf.assign(mModel.meshes.size(), -1);
        mMaxJoint.clear();
        buildRigNodes();
        buildSkins();
        for (std::size_t a = 0; a < mModel.animations.size(); ++a) {
            mRig->animations.push_back(animation(a));
        }
        mMoves.assign(mRig->nodes.size(), 0);
        for (const Animation& a : mRig->animations) {
            for (const AnimationChannel& c : a.channels) {
                if (c.path != AnimatedPath::Weights) mMoves[c.node] = 1;
            }
        }
        // Parents come first, so one pass carries an animated ancestor down to every descendant.
        for (std::size_t i = 0; i < mRig->nodes.size(); ++i) {
            const int parent = mRig->nodes[i].parent;
            if (parent >= 0 && mMoves[static_cast<std::size_t>(parent)]) mMoves[i] = 1;
        }
    }

    // Whether node `index` (a glTF index) or one of its ancestors is moved by an animation.
    bool moves(int index) const {
        return mRig &&
               mMoves[static_cast<std::size_t>(mRigNodeOf[static_cast<std::size_t>(index)])];
    }

    // Every node, parents before children. The glTF node hierarchy is a forest (glTF 2.0, 3.5.3):
    // a node with two parents or on a cycle has no single world transform to animate.
    void buildRigNodes() {
        const std::size_t count = mModel.nodes.size();
        std::vector<int> parent(count, -1);
        for (std::size_t i = 0; i < count; ++i) {
            for (const int c : mModel.nodes[i].children) {
                if (c < 0 || static_cast<std::size_t>(c) >= count) {
                    fail("node " + std::to_string(i) + " has child " + std::to_string(c) +
                         ", which does not exist");
                }
                if (parent[static_cast<std::size_t>(c)] >= 0) {
                    fail("node " + std::to_string(c) +
                         " has two parents; an animated file's node hierarchy must be a tree");
                }
                parent[static_cast<std::size_t>(c)] = static_cast<int>(i);
            }
        }
        std::vector<int> order; // breadth first from the roots
        for (std::size_t i = 0; i < count; ++i) {
            if (parent[i] < 0) order.push_back(static_cast<int>(i));
        }
        mRigNodeOf.assign(count, -1);
        for (std::size_t k = 0; k < order.size(); ++k) {
            const auto node = static_cast<std::size_t>(order[k]);
            mRigNodeOf[node] = static_cast<int>(k);
            for (const int c : mModel.nodes[node].children)
                order.push_back(c);
        }
        if (order.size() != count) fail("the node hierarchy has a cycle");
        mGltfNodeOf = order;
        for (const int g : order) {
            const int p = parent[static_cast<std::size_t>(g)];
            mRig->nodes.push_back(rigNode(g, p < 0 ? -1 : mRigNodeOf[static_cast<std::size_t>(p)]));
        }
    }

    RigNode rigNode(int index, int parent) const {
        const tinygltf::Node& n = mModel.nodes[static_cast<std::size_t>(index)];
        const std::string where = "node " + std::to_string(index);
        RigNode r;
        r.name = n.name;
        r.parent = parent;
        r.hasMatrix = n.matrix.size() == 16;
        if (r.hasMatrix) r.matrix = localMatrix(n);
        const auto f = [](double v) { return static_cast<float>(v); };
        if (n.translation.size() == 3)
            r.rest.translation = {f(n.translation[0]), f(n.translation[1]), f(n.translation[2])};
        if (n.rotation.size() == 4)
            r.rest.rotation =
                glm::quat(f(n.rotation[3]), f(n.rotation[0]), f(n.rotation[1]), f(n.rotation[2]));
        if (n.scale.size() == 3) r.rest.scale = {f(n.scale[0]), f(n.scale[1]), f(n.scale[2])};
        const bool meshValid =
            n.mesh >= 0 && static_cast<std::size_t>(n.mesh) < mModel.meshes.size();
        const std::size_t targets =
            meshValid ? morphTargetCountOf(mModel.meshes[static_cast<std::size_t>(n.mesh)]) : 0;
        // The default morph weights: the node's, else its mesh's, else zero (glTF 2.0, 3.7.2.2).
        const std::vector<double>& given =
            !n.weights.empty() || !meshValid
                ? n.weights
                : mModel.meshes[static_cast<std::size_t>(n.mesh)].weights;
        if (!given.empty() && given.size() != targets) {
            fail(where + ": has " + std::to_string(given.size()) + " morph weights, its mesh " +
                 std::to_string(targets) + " morph targets");
        }
        r.weights.assign(targets, 0.0f);
        for (std::size_t k = 0; k < given.size(); ++k)
            r.weights[k] = f(given[k]);
        float sum = 0.0f;
        for (int i = 0; i < 16; ++i)
            sum += glm::value_ptr(r.matrix)[i];
        sum += r.rest.translation.x + r.rest.translation.y + r.rest.translation.z +
               r.rest.rotation.x + r.rest.rotation.y + r.rest.rotation.z + r.rest.rotation.w +
               r.rest.scale.x + r.rest.scale.y + r.rest.scale.z;
        for (const float w : r.weights)
            sum += w;
        if (!std::isfinite(sum)) fail(where + ": its transform or morph weights are not finite");
        return r;
    }

    void buildSkins() {
        for (std::size_t s = 0; s < mModel.skins.size(); ++s) {
            const tinygltf::Skin& skin = mModel.skins[s];
            const std::string where = "skin " + std::to_string(s);
            Skin out;
            out.name = skin.name;
            if (skin.joints.empty()) fail(where + ": has no joints");
            for (const int j : skin.joints) {
                if (j < 0 || static_cast<std::size_t>(j) >= mModel.nodes.size())
                    fail(where + ": joint node " + std::to_string(j) + " does not exist");
                out.joints.push_back(
                    static_cast<uint32_t>(mRigNodeOf[static_cast<std::size_t>(j)]));
            }
            out.inverseBind.assign(out.joints.size(), glm::mat4(1.0f));
            if (skin.inverseBindMatrices >= 0) {
                if (static_cast<std::size_t>(skin.inverseBindMatrices) >= mModel.accessors.size())
                    fail(where + ": inverseBindMatrices accessor " +
                         std::to_string(skin.inverseBindMatrices) + " does not exist");
                if (mModel.accessors[static_cast<std::size_t>(skin.inverseBindMatrices)].type !=
                    TINYGLTF_TYPE_MAT4)
                    fail(where + ": inverseBindMatrices is not MAT4");
                const std::vector<float> m = readFloats(skin.inverseBindMatrices, 16);
                if (m.size() / 16 < out.joints.size()) {
                    fail(where + ": inverseBindMatrices has " + std::to_string(m.size() / 16) +
                         " matrices, fewer than its " + std::to_string(out.joints.size()) +
                         " joints");
                }
                for (std::size_t j = 0; j < out.joints.size(); ++j) {
                    for (int i = 0; i < 16; ++i) {
                        const float v = m[16 * j + static_cast<std::size_t>(i)];
                        if (!std::isfinite(v))
                            fail(where + ": inverse bind matrix " + std::to_string(j) +
                                 " is not finite");
                        glm::value_ptr(out.inverseBind[j])[i] = v; // column-major, as glTF
                    }
                }
            }
            mRig->skins.push_back(std::move(out));
        }
    }

    static Interpolation interpolationOf(const std::string& name, bool& known) {
        known = true;
        if (name.empty() || name == "LINEAR") return Interpolation::Linear;
        if (name == "STEP") return Interpolation::Step;
        if (name == "CUBICSPLINE") return Interpolation::CubicSpline;
        known = false;
        return Interpolation::Linear;
    }

    // One sampler's keys, checked: the times increase, every value is finite. Its component count
    // is its output accessor's until a channel says what it animates.
    AnimationSampler animationSampler(const tinygltf::AnimationSampler& in,
                                      const std::string& where, std::size_t& outputElements) const {
        AnimationSampler out;
        bool known = false;
        out.interpolation = interpolationOf(in.interpolation, known);
        if (!known)
            fail(where + ": interpolation '" + in.interpolation +
                 "' is not LINEAR, STEP or CUBICSPLINE");
        const bool cubic = out.interpolation == Interpolation::CubicSpline;
        for (const int a : {in.input, in.output}) {
            if (a < 0 || static_cast<std::size_t>(a) >= mModel.accessors.size())
                fail(where + ": accessor " + std::to_string(a) + " does not exist");
        }
        if (mModel.accessors[static_cast<std::size_t>(in.input)].type != TINYGLTF_TYPE_SCALAR)
            fail(where + ": input accessor " + std::to_string(in.input) + " is not SCALAR");
        out.times = readFloats(in.input, 1);
        checkSamplerTimes(out.times, cubic, mFile + ": " + where);
        const int components = tinygltf::GetNumComponentsInType(
            static_cast<uint32_t>(mModel.accessors[static_cast<std::size_t>(in.output)].type));
        if (components != 1 && components != 3 && components != 4)
            fail(where + ": output accessor " + std::to_string(in.output) +
                 " is not SCALAR, VEC3 or VEC4");
        out.values = readFloats(in.output, components);
        out.components = static_cast<uint32_t>(components);
        outputElements = out.values.size() / static_cast<std::size_t>(components);
        checkSamplerValues(out.values, out.components, mFile + ": " + where);
        return out;
    }

    Animation animation(std::size_t index) const {
        const tinygltf::Animation& in = mModel.animations[index];
        const std::string where = "animation " + std::to_string(index);
        Animation out;
        out.name = in.name;
        std::vector<std::size_t> outputElements(in.samplers.size(), 0);
        for (std::size_t k = 0; k < in.samplers.size(); ++k) {
            out.samplers.push_back(animationSampler(
                in.samplers[k], where + " sampler " + std::to_string(k), outputElements[k]));
            out.duration = std::max(out.duration, out.samplers.back().times.back());
        }
        for (std::size_t c = 0; c < in.channels.size(); ++c) {
            const std::string w = where + " channel " + std::to_string(c);
            if (auto channel = animationChannel(in.channels[c], w, out, outputElements, where)) {
                out.channels.push_back(*channel);
            }
        }
        return out;
    }

    static std::optional<AnimatedPath> pathOf(const std::string& name) {
        if (name == "translation") return AnimatedPath::Translation;
        if (name == "rotation") return AnimatedPath::Rotation;
        if (name == "scale") return AnimatedPath::Scale;
        if (name == "weights") return AnimatedPath::Weights;
        return std::nullopt;
    }

    // A channel, checked against its sampler and its node; none for one this loader does not
    // play (no target node, as KHR_animation_pointer writes them, or another path).
    std::optional<AnimationChannel> animationChannel(const tinygltf::AnimationChannel& in,
                                                     const std::string& where, Animation& anim,
                                                     const std::vector<std::size_t>& elements,
                                                     const std::string& animWhere) const {
        if (in.sampler < 0 || static_cast<std::size_t>(in.sampler) >= anim.samplers.size()) {
            fail(where + ": sampler " + std::to_string(in.sampler) + " is past the animation's " +
                 std::to_string(anim.samplers.size()) + " samplers");
        }
        const auto path = pathOf(in.target_path);
        if (in.target_node < 0 || !path) {
            mReport.warnings.push_back(where + ": no node or path this loader plays; ignored");
            return std::nullopt;
        }
        if (static_cast<std::size_t>(in.target_node) >= mModel.nodes.size()) {
            fail(where + ": target node " + std::to_string(in.target_node) +
                 " does not exist (the file has " + std::to_string(mModel.nodes.size()) +
                 " nodes)");
        }
        const RigNode& node = mRig->nodes[static_cast<std::size_t>(
            mRigNodeOf[static_cast<std::size_t>(in.target_node)])];
        const std::string nodeName = "node " + std::to_string(in.target_node);
        if (node.hasMatrix && *path != AnimatedPath::Weights)
            fail(where + ": targets " + nodeName + ", which has a matrix (glTF animates TRS only)");
        const auto s = static_cast<std::size_t>(in.sampler);
        AnimationSampler& sampler = anim.samplers[s];
        const uint32_t need = *path == AnimatedPath::Rotation  ? 4u
                              : *path == AnimatedPath::Weights ? 1u
                                                               : 3u;
        if (sampler.values.size() / std::max<std::size_t>(elements[s], 1) != need &&
            elements[s] > 0) {
            fail(where + ": sampler " + std::to_string(s) + "'s output has " +
                 std::to_string(sampler.values.size() / elements[s]) + " components, " +
                 in.target_path + " needs " + std::to_string(need));
        }
        std::size_t perKey = 0; // morph targets a key: none but for weights
        if (*path == AnimatedPath::Weights) {
            perKey = node.weights.size();
            if (perKey == 0)
                fail(where + ": animates the weights of " + nodeName +
                     ", whose mesh has no morph targets");
        }
        checkSamplerCount(elements[s], sampler.times.size(), perKey,
                          sampler.interpolation == Interpolation::CubicSpline,
                          mFile + ": " + animWhere + " sampler " + std::to_string(s));
        sampler.components = static_cast<uint32_t>(perKey > 0 ? perKey : need);
        return AnimationChannel{
            static_cast<uint32_t>(s),
            static_cast<uint32_t>(mRigNodeOf[static_cast<std::size_t>(in.target_node)]), *path};
    }

    // A mesh instance goes into the rig when its vertices or its world transform can change.
    bool rigBound(int nodeIndex, const tinygltf::Mesh& mesh) const {
        if (!mRig || isCage(mesh)) return false; // cages are refined once, where they stand
        return moves(nodeIndex) || mModel.nodes[static_cast<std::size_t>(nodeIndex)].skin >= 0 ||
               morphTargetCountOf(mesh) > 0;
    }

    void addRigInstance(int nodeIndex) {
        const tinygltf::Node& node = mModel.nodes[static_cast<std::size_t>(nodeIndex)];
        const uint32_t mesh = rigMesh(node.mesh, nodeIndex);
        MeshInstance instance{
            static_cast<uint32_t>(mRigNodeOf[static_cast<std::size_t>(nodeIndex)]), mesh, -1};
        if (node.skin >= 0) {
            const std::string where = "node " + std::to_string(nodeIndex);
            if (static_cast<std::size_t>(node.skin) >= mRig->skins.size())
                fail(where + " has skin " + std::to_string(node.skin) + ", which does not exist");
            if (mRig->meshes[mesh].joints.empty())
                fail(where + " has a skin, but mesh '" + mRig->meshes[mesh].name +
                     "' has no JOINTS_0 and WEIGHTS_0");
            const std::size_t joints =
                mRig->skins[static_cast<std::size_t>(node.skin)].joints.size();
            const JointUse& use = mMaxJoint[mesh];
            if (use.joint >= joints) {
                fail("mesh '" + mRig->meshes[mesh].name + "' primitive " +
                     std::to_string(use.primitive) + " vertex " + std::to_string(use.vertex) +
                     ": joint " + std::to_string(use.joint) + " is out of range of skin " +
                     std::to_string(node.skin) + "'s " + std::to_string(joints) + " joints");
            }
            instance.skin = node.skin;
        }
        // A mesh whose triangles were all degenerate draws nothing, as on the static path.
        if (!mRig->meshes[mesh].vertices.empty()) mRig->instances.push_back(instance);
    }

    // The largest joint index a mesh's vertices name, and where: checked against each skin.
    struct JointUse {
        uint32_t joint = 0;
        std::size_t primitive = 0, vertex = 0;
    };

    uint32_t rigMesh(int meshIndex, int nodeIndex) {
        int& slot = mRigMeshOf[static_cast<std::size_t>(meshIndex)];
        if (slot >= 0) return static_cast<uint32_t>(slot);
        const tinygltf::Mesh& mesh = mModel.meshes[static_cast<std::size_t>(meshIndex)];
        const std::size_t targets = morphTargetCountOf(mesh);
        std::size_t withJoints = 0;
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
            const tinygltf::Primitive& prim = mesh.primitives[p];
            if (prim.targets.size() != targets)
                fail("mesh '" + mesh.name + "': primitive " + std::to_string(p) + " has " +
                     std::to_string(prim.targets.size()) + " morph targets, primitive 0 has " +
                     std::to_string(targets));
            withJoints += prim.attributes.count("JOINTS_0") && prim.attributes.count("WEIGHTS_0");
        }
        if (withJoints != 0 && withJoints != mesh.primitives.size())
            fail("mesh '" + mesh.name + "': some primitives have JOINTS_0 and WEIGHTS_0, some not");
        RigMesh out;
        out.name = mesh.name;
        out.targets.resize(targets);
        std::vector<char> anyPosition(targets, 0), anyNormal(targets, 0);
        JointUse use;
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
            if (!trianglePrimitive(mesh, mesh.primitives[p])) continue;
            appendRigPrimitive(out, mesh, p, withJoints != 0, nodeIndex, use, anyPosition,
                               anyNormal);
        }
        for (std::size_t k = 0; k < targets; ++k) {
            if (!anyPosition[k]) out.targets[k].positions.clear();
            if (!anyNormal[k]) out.targets[k].normals.clear();
        }
        slot = static_cast<int>(mRig->meshes.size());
        mRig->meshes.push_back(std::move(out));
        mMaxJoint.push_back(use);
        return static_cast<uint32_t>(slot);
    }

    // JOINTS_0 (unsigned byte or short, glTF 2.0, 3.7.3.1) and WEIGHTS_0 (float or normalised
    // unsigned byte or short), the weights scaled to sum to 1.
    void readSkinning(const tinygltf::Primitive& prim, const std::string& where,
                      std::size_t vertexCount, std::vector<float>& joints,
                      std::vector<float>& weights) const {
        const int j = prim.attributes.at("JOINTS_0");
        const tinygltf::Accessor& a = accessor(j);
        if ((a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
             a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) ||
            a.normalized)
            fail(where + ": JOINTS_0 is not unsigned byte or short");
        joints = readFloats(j, 4);
        const int w = prim.attributes.at("WEIGHTS_0");
        const tinygltf::Accessor& b = accessor(w);
        if (b.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !b.normalized)
            fail(where + ": WEIGHTS_0 is neither float nor normalised");
        weights = readFloats(w, 4);
        if (joints.size() != 4 * vertexCount || weights.size() != 4 * vertexCount)
            fail(where + ": JOINTS_0 or WEIGHTS_0 count differs from POSITION");
        for (std::size_t v = 0; v < vertexCount; ++v) {
            float sum = 0.0f;
            for (std::size_t c = 0; c < 4; ++c) {
                const float x = weights[4 * v + c];
                if (!(x >= 0.0f) || !std::isfinite(x))
                    fail(where + ": WEIGHTS_0 of vertex " + std::to_string(v) +
                         " is negative or not a finite number");
                sum += x;
            }
            for (std::size_t c = 0; c < 4; ++c) {
                // All zero: bound to its first joint rather than collapsed to the origin.
                weights[4 * v + c] = sum > 0.0f ? weights[4 * v + c] / sum : (c == 0 ? 1.0f : 0.0f);
            }
        }
    }

    // Morph target `k`'s attribute `name` of a primitive: empty when it has none, else one
    // displacement a vertex.
    std::vector<float> readTarget(const tinygltf::Primitive& prim, std::size_t k, const char* name,
                                  const std::string& where, std::size_t vertexCount) const {
        const auto it = prim.targets[k].find(name);
        if (it == prim.targets[k].end()) return {};
        std::vector<float> d = readFloats(it->second, 3);
        const std::string w = where + " morph target " + std::to_string(k) + ": " + name;
        if (d.size() != 3 * vertexCount)
            fail(w + " has " + std::to_string(d.size() / 3) + " elements, the primitive " +
                 std::to_string(vertexCount) + " vertices");
        for (const float x : d) {
            if (!std::isfinite(x)) fail(w + " has a value that is not a finite number");
        }
        return d;
    }

    // A primitive's triangles in mesh space, with per-vertex joints, weights and target deltas.
    void appendRigPrimitive(RigMesh& out, const tinygltf::Mesh& mesh, std::size_t p, bool skinned,
                            int nodeIndex, JointUse& use, std::vector<char>& anyPosition,
                            std::vector<char>& anyNormal) {
        const tinygltf::Primitive& prim = mesh.primitives[p];
        const std::string where = "mesh '" + mesh.name + "' primitive " + std::to_string(p);
        const PrimitiveData d = readPrimitive(mesh, prim);
        std::vector<float> joints, weights;
        if (skinned) readSkinning(prim, where, d.vertexCount, joints, weights);
        std::vector<std::vector<float>> dp, dn;
        for (std::size_t k = 0; k < out.targets.size(); ++k) {
            dp.push_back(readTarget(prim, k, "POSITION", where, d.vertexCount));
            dn.push_back(readTarget(prim, k, "NORMAL", where, d.vertexCount));
            anyPosition[k] |= !dp.back().empty();
            anyNormal[k] |= !dn.back().empty();
        }
        const auto delta = [](const std::vector<float>& v, uint32_t i) {
            return v.empty() ? glm::vec3(0.0f) : glm::vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
        };
        for (std::size_t t = 0; t + 2 < d.tris.size(); t += 3) {
            Vertex v[3];
            for (int k = 0; k < 3; ++k) {
                v[k] = corner(d, d.tris[t + k], glm::mat4(1.0f), glm::mat3(1.0f));
                checkWorldPosition(v[k].position, nodeIndex);
            }
            if (!finishNormals(v, !d.n.empty())) continue;
            out.vertices.insert(out.vertices.end(), {v[0], v[1], v[2]});
            out.triangleMaterial.push_back(d.material);
            for (std::size_t k = 0; k < 3; ++k) {
                const uint32_t i = d.tris[t + k];
                if (skinned) {
                    const glm::uvec4 j(joints[4 * i], joints[4 * i + 1], joints[4 * i + 2],
                                       joints[4 * i + 3]);
                    for (int c = 0; c < 4; ++c) {
                        if (j[c] >= use.joint) use = {j[c], p, i};
                    }
                    out.joints.push_back(j);
                    out.weights.emplace_back(weights[4 * i], weights[4 * i + 1], weights[4 * i + 2],
                                             weights[4 * i + 3]);
                }
                for (std::size_t m = 0; m < out.targets.size(); ++m) {
                    out.targets[m].positions.push_back(delta(dp[m], i));
                    out.targets[m].normals.push_back(delta(dn[m], i));
                }
            }
        }
    }

    // The rig's instances at the rest pose, added to the bounds the camera is framed on (a file
    // whose every mesh moves has no static vertices to frame), and held to the coordinate limit
    // the static triangles are.
    void addRestBounds(glm::vec3& lo, glm::vec3& hi) {
        std::vector<glm::mat4> world(mRig->nodes.size());
        for (std::size_t i = 0; i < world.size(); ++i) {
            const RigNode& n = mRig->nodes[i];
            const glm::mat4 local = n.hasMatrix
                                        ? n.matrix
                                        : glm::translate(glm::mat4(1.0f), n.rest.translation) *
                                              glm::mat4_cast(n.rest.rotation) *
                                              glm::scale(glm::mat4(1.0f), n.rest.scale);
            world[i] = n.parent < 0 ? local : world[static_cast<std::size_t>(n.parent)] * local;
        }
        for (const MeshInstance& inst : mRig->instances) {
            const RigMesh& m = mRig->meshes[inst.mesh];
            for (std::size_t v = 0; v < m.vertices.size(); ++v) {
                glm::mat4 toWorld = world[inst.node];
                if (inst.skin >= 0) {
                    // Linear blend skinning at rest (glTF 2.0, 3.7.3.3).
                    const Skin& s = mRig->skins[static_cast<std::size_t>(inst.skin)];
                    toWorld = glm::mat4(0.0f);
                    for (int c = 0; c < 4; ++c) {
                        const uint32_t j = m.joints[v][c];
                        toWorld += m.weights[v][c] * world[s.joints[j]] * s.inverseBind[j];
                    }
                }
                const glm::vec3 p(toWorld * glm::vec4(m.vertices[v].position, 1.0f));
                checkWorldPosition(p, mGltfNodeOf[inst.node]);
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
        }
    }

    void finish() {
        glm::vec3 lo = mScene.boundsMin(), hi = mScene.boundsMax();
        if (mRig) addRestBounds(lo, hi);
        const glm::vec3 centre = 0.5f * (lo + hi);
        const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
        if (!mHaveCamera) {
            // Frame the whole scene from the front, slightly above.
            const glm::vec3 dir = glm::normalize(glm::vec3(0.0f, 0.25f, 1.0f));
            mScene.camera.yfov = glm::radians(45.0f);
            mScene.camera.position = centre + dir * (radius / std::sin(0.5f * mScene.camera.yfov));
            mScene.camera.forward = -dir;
            mScene.camera.up = {0, 1, 0};
            mScene.cameraFramed = true;
        }
        if (mScene.lights.empty()) {
            // Unlit files get a sun from above-front-left so shapes and shadows read clearly.
            Light sun;
            sun.type = LightType::Directional;
            sun.direction = glm::normalize(glm::vec3(0.4f, -1.0f, -0.6f));
            sun.intensity = 3.0f;
            sun.color = {1.0f, 0.97f, 0.92f};
            mScene.lights.push_back(sun);
            mScene.sky.ambient = 0.35f;
        }
    }

    const tinygltf::Model& mModel;
    std::string mFile;
    GltfLoadReport& mReport;
    GltfLoadOptions mOptions;
    Scene mScene;
    std::vector<int> mTextureOfImage;
    mutable std::map<int, std::vector<unsigned char>> mDense; // see dense()
    std::vector<UvTransform> mMaterialUv; // per material, the default material's last
    uint32_t mDefaultMaterial = 0;
    bool mHaveCamera = false;
    // What moves: null while nothing does. The rig's nodes are every glTF node, parents first.
    std::shared_ptr<Rig> mRig;
    std::vector<int> mRigNodeOf;     // per glTF node, its index in mRig->nodes
    std::vector<int> mGltfNodeOf;    // per rig node, its glTF index
    std::vector<char> mMoves;        // per rig node: it or an ancestor is animated
    std::vector<int> mRigMeshOf;     // per glTF mesh, its index in mRig->meshes (-1: not yet)
    std::vector<JointUse> mMaxJoint; // per rig mesh
};

} // namespace

namespace {

// Deeper JSON than this is refused before tinygltf parses it: its parser recurses once per
// level, and 20,000 levels (inside `extras`, say) overflowed the stack. Real glTF files nest a
// dozen levels; extras written by tools stay far below this.
constexpr int kMaxJsonDepth = 256;

// The deepest nesting of objects and arrays in `json` (strings and escapes skipped), stopping
// once past kMaxJsonDepth.
int jsonDepth(std::string_view json) {
    int depth = 0, deepest = 0;
    bool inString = false, escaped = false;
    for (const char c : json) {
        if (inString) {
            if (escaped) {
                escaped = false;
            } else if (c == '\\') {
                escaped = true;
            } else if (c == '"') {
                inString = false;
            }
            continue;
        }
        if (c == '"') {
            inString = true;
        } else if (c == '{' || c == '[') {
            deepest = std::max(deepest, ++depth);
            if (deepest > kMaxJsonDepth) break;
        } else if (c == '}' || c == ']') {
            --depth;
        }
    }
    return deepest;
}

} // namespace

namespace {

// tinygltf reads a model's external files (buffers, images) through these: a URI may only name
// a file inside the model's folder (a `uri` of ../../../../etc/shadow was read),
// unless GltfLoadOptions::anyPath allows it. `~` and variables are not expanded.
struct UriGuard {
    std::filesystem::path root; // weakly canonical
    bool anyPath = false;
    // The files the document names as images and as buffers (weakly canonical): each is read
    // through io::readInputFile with its kind's limit.
    std::vector<std::filesystem::path> imageFiles, bufferFiles;
};

bool insideRoot(const std::string& file, const UriGuard& g) {
    if (g.anyPath) return true;
    std::error_code ec;
    const std::filesystem::path p = std::filesystem::weakly_canonical(file, ec);
    if (ec) return false;
    auto r = g.root.begin();
    auto q = p.begin();
    for (; r != g.root.end(); ++r, ++q) {
        if (q == p.end() || *q != *r) return false;
    }
    return true;
}

// Existence is answered truthfully, so that reading an outside file reaches guardedRead and
// its message says why it was refused, not just "not found". stat(), not tinygltf's fopen():
// opening a FIFO to see whether it exists blocked forever.
bool guardedExists(const std::string& file, void*) {
    std::error_code ec;
    return std::filesystem::exists(file, ec);
}

bool listed(const std::vector<std::filesystem::path>& files, const std::filesystem::path& p) {
    return std::find(files.begin(), files.end(), p) != files.end();
}

std::string noExpansion(const std::string& file, void*) {
    return file;
}

bool guardedRead(std::vector<unsigned char>* out, std::string* err, const std::string& file,
                 void* user) {
    if (!insideRoot(file, *static_cast<UriGuard*>(user))) {
        if (err) {
            *err += "refusing to read " + file + ": it lies outside the model's folder";
        }
        return false;
    }
    const auto& guard = *static_cast<UriGuard*>(user);
    std::error_code ec;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(file, ec);
    const bool image = listed(guard.imageFiles, canonical) && !listed(guard.bufferFiles, canonical);
    try {
        const std::string bytes = io::readInputFile(file, image ? io::limits::kImageFileBytes
                                                                : io::limits::kGltfBufferBytes);
        out->assign(bytes.begin(), bytes.end());
        return true;
    } catch (const io::InputError& e) {
        if (err) *err += e.what();
        return false;
    }
}

bool noWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "gazetrace does not write glTF files";
    return false;
}

} // namespace

namespace {

// The file's bytes and, inside them, its JSON (all of a .gltf, a GLB's first chunk), checked
// before tinygltf sees them: read once, through io::readInputFile, so the text checked here is
// the text tinygltf parses.
struct Document {
    std::string bytes;
    std::string_view json;
};

Document readDocument(const std::filesystem::path& path, bool glb) {
    const std::string file = path.string();
    Document d;
    try {
        // A GLB carries its binary buffer, so it gets a buffer's limit.
        d.bytes = io::readInputFile(path, glb ? io::limits::kGltfBufferBytes
                                              : io::limits::kGltfDocumentBytes);
    } catch (const io::InputError& e) {
        throw LoadError(e.what());
    }
    d.json = d.bytes;
    if (glb) {
        const GlbLayout layout = glbLayout(d.bytes, file);
        d.json = d.json.substr(layout.jsonOffset, layout.jsonLength);
    }
    checkJsonText(d.json, file);
    if (const int depth = jsonDepth(d.json); depth > kMaxJsonDepth) {
        throw LoadError(file + ": JSON nested more than " + std::to_string(kMaxJsonDepth) +
                        " levels deep; refused before parsing");
    }
    return d;
}

std::vector<std::filesystem::path> canonicalFiles(const std::vector<std::string>& uris,
                                                  const std::string& baseDir) {
    std::vector<std::filesystem::path> out;
    for (const std::string& uri : uris) {
        std::error_code ec;
        out.push_back(std::filesystem::weakly_canonical(
            baseDir.empty() ? std::filesystem::path(uri) : std::filesystem::path(baseDir) / uri,
            ec));
    }
    return out;
}

void checkModel(const tinygltf::Model& model, const std::string& file) {
    for (const std::string& e : model.extensionsRequired) {
        if (e != "KHR_lights_punctual" && e != "KHR_materials_emissive_strength" &&
            e != "KHR_texture_transform" && e != "KHR_materials_unlit" &&
            e != "KHR_mesh_quantization" && e != "KHR_materials_transmission" &&
            e != "KHR_materials_ior") {
            throw LoadError(file + ": requires unsupported extension " + e);
        }
    }
    for (const tinygltf::Buffer& b : model.buffers) {
        if (b.data.empty()) throw LoadError(file + ": buffer '" + b.uri + "' is empty or missing");
    }
}

} // namespace

Scene loadGltf(const std::filesystem::path& path, GltfLoadReport* report,
               const GltfLoadOptions& options) {
    GltfLoadReport local;
    GltfLoadReport& rep = report ? *report : local;
    const std::string file = path.string();
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw LoadError(file + ": no such file");
    if (std::filesystem::is_directory(path, ec))
        throw LoadError(file + ": is a folder, not a glTF file");
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext != ".gltf" && ext != ".glb") {
        throw LoadError(file + ": not a .gltf or .glb file");
    }
    const bool glb = ext == ".glb";
    const Document doc = readDocument(path, glb);
    const GltfDocumentFacts facts = validateGltfJson(doc.json, file);
    // tinygltf's base folder for relative URIs, as LoadASCIIFromFile would take it.
    const std::string baseDir =
        file.find_last_of('/') == std::string::npos ? "" : file.substr(0, file.find_last_of('/'));
    tinygltf::TinyGLTF loader;
    UriGuard guard;
    {
        std::error_code gec;
        guard.root = std::filesystem::weakly_canonical(
            path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path(), gec);
        guard.anyPath = options.anyPath;
        guard.imageFiles = canonicalFiles(facts.imageFiles, baseDir);
        guard.bufferFiles = canonicalFiles(facts.bufferFiles, baseDir);
    }
    loader.SetFsCallbacks({guardedExists, noExpansion, guardedRead, noWrite, &guard});
    ImageLoaderState state{&rep.warnings, file, &facts.sampledImage, options.maxTextureBytes};
    loader.SetImageLoader(loadImage, &state);
    tinygltf::Model model;
    std::string err, warn;
    // Both sizes fit: the limits on what readDocument reads are below 4 GiB.
    const bool ok =
        glb ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                          reinterpret_cast<const unsigned char*>(doc.bytes.data()),
                                          static_cast<unsigned int>(doc.bytes.size()), baseDir)
            : loader.LoadASCIIFromString(&model, &err, &warn, doc.json.data(),
                                         static_cast<unsigned int>(doc.json.size()), baseDir);
    if (!warn.empty()) rep.warnings.push_back(oneLine(warn));
    if (!ok) throw LoadError(file + ": " + (err.empty() ? "cannot parse glTF" : oneLine(err)));
    checkModel(model, file);
    try {
        return Loader(model, file, rep, options).load();
    } catch (const std::length_error& e) {
        // An accessor count of 2^62, say: "cannot create std::vector larger than max_size()"
        // alone did not say which file.
        throw LoadError(file + ": a size in the file is too large to hold (" + e.what() + ")");
    } catch (const std::bad_alloc&) {
        throw LoadError(file + ": out of memory while loading (a size in the file too large?)");
    }
}

Scene loadScene(const std::string& spec, GltfLoadReport* report, const GltfLoadOptions& options) {
    if (spec.empty()) {
        throw LoadError(
            "the scene is empty: give builtin:NAME, FILE.gltf, FILE.glb or cubemap:FILE");
    }
    if (spec.rfind("builtin:", 0) == 0) return makeBuiltin(spec);
    if (spec.rfind("cubemap:", 0) == 0) {
        // The thesis's experiment setup (6.1): no geometry, the camera looks into a panorama.
        Scene s;
        s.name = spec;
        s.environment = loadEnvironment(spec.substr(8), report ? &report->warnings : nullptr);
        s.camera.position = {0.0f, 0.0f, 0.0f};
        s.camera.forward = {0.0f, 0.0f, -1.0f};
        s.camera.yfov = glm::radians(75.0f);
        return s;
    }
    return loadGltf(spec, report, options);
}

} // namespace gt::scene
