#include "scene/gltf_validate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <numbers>
#include <optional>

#include <nlohmann/json.hpp>

#include "checked_size.hpp"
#include "core/error.hpp"
#include "input_file.hpp"
#include "limits.hpp"

namespace gt::scene {

namespace {

using nlohmann::json;

// The length of the UTF-8 sequence starting at `s[i]`, or 0 when it is not well formed (an
// overlong form, a surrogate, past U+10FFFF, or cut short).
std::size_t utf8Sequence(std::string_view s, std::size_t i) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = byte(i);
    if (c < 0x80) {
        return 1;
    }
    std::size_t n = 0;
    unsigned char lo = 0x80, hi = 0xBF; // the allowed range of the second byte
    if (c >= 0xC2 && c <= 0xDF) {
        n = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
        n = 3;
        if (c == 0xE0) {
            lo = 0xA0;
        }
        if (c == 0xED) {
            hi = 0x9F;
        }
    } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4;
        if (c == 0xF0) {
            lo = 0x90;
        }
        if (c == 0xF4) {
            hi = 0x8F;
        }
    } else {
        return 0;
    }
    if (s.size() - i < n) {
        return 0;
    }
    if (byte(i + 1) < lo || byte(i + 1) > hi) {
        return 0;
    }
    for (std::size_t k = 2; k < n; ++k) {
        if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) {
            return 0;
        }
    }
    return n;
}

std::string percentDecoded(const std::string& uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        const auto hex = [](char c) -> int {
            if (c >= '0' && c <= '9') {
                return c - '0';
            }
            if (c >= 'a' && c <= 'f') {
                return c - 'a' + 10;
            }
            if (c >= 'A' && c <= 'F') {
                return c - 'A' + 10;
            }
            return -1;
        };
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
            out += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

std::string at(const std::string& where, std::size_t i) {
    return where + "[" + std::to_string(i) + "]";
}

std::string describe(const json& v) {
    if (v.is_number_float()) {
        char s[64];
        std::snprintf(s, sizeof(s), "%.10g", v.get<double>());
        return s;
    }
    const std::string text = v.dump();
    return text.size() > 40 ? text.substr(0, 40) + "..." : text;
}

struct ViewInfo {
    std::uint64_t length = 0, stride = 0; // stride 0: tightly packed
};

// One pass over the document; every refusal names the field as a JSON path.
class DocumentChecker {
public:
    DocumentChecker(const json& root, std::string file) : mRoot(root), mFile(std::move(file)) {}

    GltfDocumentFacts check() {
        if (!mRoot.is_object()) {
            refuse("the document", "is not a JSON object");
        }
        for (const char* name :
             {"accessors", "animations", "buffers", "bufferViews", "cameras", "images", "materials",
              "meshes", "nodes", "samplers", "scenes", "skins", "textures"}) {
            mCount[name] = objects(mRoot, name, name).size();
        }
        mCount["lights"] = lightList().size();
        checkAsset();
        checkBuffers();
        checkBufferViews();
        checkAccessors();
        checkMeshes();
        checkNodes();
        checkScenes();
        checkLights();
        checkCameras();
        checkSkinsAndAnimations();
        checkMaterials();
        return facts();
    }

private:
    [[noreturn]] void refuse(const std::string& field, const std::string& what) const {
        throw LoadError(mFile + ": " + field + " " + what);
    }

    // glTF 2.0, 3.2 "Asset": the version is "major.minor", and a 2.0 reader reads major 2 only
    // (a "3.0" file loaded as if it were 2.0). A missing asset is tinygltf's to report.
    void checkAsset() const {
        const json* asset = member(mRoot, "asset");
        if (!asset || !asset->is_object()) {
            return;
        }
        const json* version = member(*asset, "version");
        if (!version) {
            refuse("asset.version", "is missing");
        }
        const std::string text = version->is_string() ? version->get<std::string>() : "";
        if (text.rfind("2.", 0) != 0 || text.size() < 3 ||
            text.find_first_not_of("0123456789", 2) != std::string::npos) {
            refuse("asset.version", "is " + describe(*version) + ", must be 2.x (glTF 2.0)");
        }
    }

    // The elements of an optional array of objects (empty when absent).
    std::vector<const json*> objects(const json& o, const char* key, const std::string& where) {
        std::vector<const json*> out;
        const json* a = array(o, key, where);
        if (!a) {
            return out;
        }
        for (std::size_t i = 0; i < a->size(); ++i) {
            if (!(*a)[i].is_object()) {
                refuse(at(where, i), "is not a JSON object");
            }
            out.push_back(&(*a)[i]);
        }
        return out;
    }
    const json* member(const json& o, const char* key) const {
        const auto it = o.find(key);
        return it == o.end() ? nullptr : &*it;
    }
    const json* array(const json& o, const char* key, const std::string& where) const {
        const json* v = member(o, key);
        if (v && !v->is_array()) {
            refuse(where, "is not an array");
        }
        return v;
    }
    const json* object(const json& o, const char* key, const std::string& where) const {
        const json* v = member(o, key);
        if (v && !v->is_object()) {
            refuse(where, "is not a JSON object");
        }
        return v;
    }

    // A non-negative integer in [lo, hi]: a negative one is refused, not read as 0, a real one
    // is refused, not dropped (tinygltf does both silently).
    std::optional<std::uint64_t> integer(const json& v, const std::string& where, std::uint64_t lo,
                                         std::uint64_t hi) const {
        std::uint64_t n = 0;
        if (v.is_number_unsigned()) {
            n = v.get<std::uint64_t>();
        } else if (v.is_number_integer()) {
            const auto s = io::nonNegative(v.get<std::int64_t>());
            if (!s) {
                refuse(where, "is " + describe(v) + ", must be >= " + std::to_string(lo));
            }
            n = *s;
        } else {
            refuse(where, "is " + describe(v) + ", must be an integer");
        }
        if (n < lo) {
            refuse(where, "is " + std::to_string(n) + ", must be >= " + std::to_string(lo));
        }
        if (n > hi) {
            refuse(where, "is " + std::to_string(n) + ", must be <= " + std::to_string(hi));
        }
        return n;
    }
    std::optional<std::uint64_t> integer(const json& o, const char* key, const std::string& where,
                                         std::uint64_t lo = 0,
                                         std::uint64_t hi = UINT64_MAX) const {
        const json* v = member(o, key);
        if (!v) {
            return std::nullopt;
        }
        return integer(*v, where + "." + key, lo, hi);
    }
    std::uint64_t required(const json& o, const char* key, const std::string& where,
                           std::uint64_t lo = 0, std::uint64_t hi = UINT64_MAX) const {
        const auto v = integer(o, key, where, lo, hi);
        if (!v) {
            refuse(where + "." + key, "is missing");
        }
        return *v;
    }
    // An index into the top-level list `list`.
    std::uint64_t indexValue(const json& v, const std::string& where, const char* list) const {
        const std::uint64_t n = *integer(v, where, 0, UINT64_MAX);
        const std::size_t count = mCount.at(list);
        if (n >= count) {
            refuse(where,
                   "is " + std::to_string(n) + ", but there " +
                       (count == 1 ? "is 1 entry" : "are " + std::to_string(count) + " entries") +
                       " in " + list);
        }
        return n;
    }
    std::optional<std::uint64_t> index(const json& o, const char* key, const std::string& where,
                                       const char* list) const {
        const json* v = member(o, key);
        if (!v) {
            return std::nullopt;
        }
        return indexValue(*v, where + "." + key, list);
    }
    std::optional<double> number(const json& o, const char* key, const std::string& where) const {
        const json* v = member(o, key);
        if (!v) {
            return std::nullopt;
        }
        if (!v->is_number()) {
            refuse(where + "." + key, "is " + describe(*v) + ", not a number");
        }
        const double d = v->get<double>();
        if (!std::isfinite(d)) {
            refuse(where + "." + key, "is not a finite number");
        }
        return d;
    }
    // An array of exactly `n` finite numbers.
    void numbers(const json& o, const char* key, const std::string& where, std::size_t n) const {
        const json* a = array(o, key, where + "." + key);
        if (!a) {
            return;
        }
        if (a->size() != n) {
            refuse(where + "." + key,
                   "has " + std::to_string(a->size()) + " numbers, must have " + std::to_string(n));
        }
        for (std::size_t i = 0; i < n; ++i) {
            if (!(*a)[i].is_number() || !std::isfinite((*a)[i].get<double>())) {
                refuse(at(where + "." + key, i), "is " + describe((*a)[i]) + ", not a number");
            }
        }
    }

    void checkBuffers();
    void checkBufferViews();
    void checkAccessors();
    void checkSparse(const json& sparse, const std::string& where, std::uint64_t count,
                     std::uint64_t elementSize);
    void checkPrimitive(const json& p, const std::string& where);
    void checkMeshes();
    void checkNodes();
    void checkScenes();
    std::vector<const json*> lightList();
    void checkLights();
    void checkCameras();
    void checkSkinsAndAnimations();
    void checkTextureInfo(const json& o, const char* key, const std::string& where);
    void checkMaterials();
    GltfDocumentFacts facts();

    const json& mRoot;
    std::string mFile;
    std::map<std::string, std::size_t, std::less<>> mCount;
    std::vector<std::uint64_t> mBufferLength;
    std::vector<ViewInfo> mView;
};

void DocumentChecker::checkBuffers() {
    for (const json* b : objects(mRoot, "buffers", "buffers")) {
        const std::string where = at("buffers", mBufferLength.size());
        mBufferLength.push_back(required(*b, "byteLength", where, 1));
        if (const json* uri = member(*b, "uri"); uri && !uri->is_string()) {
            refuse(where + ".uri", "is not a string");
        }
    }
}

void DocumentChecker::checkBufferViews() {
    for (const json* v : objects(mRoot, "bufferViews", "bufferViews")) {
        const std::string where = at("bufferViews", mView.size());
        if (!member(*v, "buffer")) {
            refuse(where + ".buffer", "is missing");
        }
        const std::uint64_t buffer = *index(*v, "buffer", where, "buffers");
        const std::uint64_t offset = integer(*v, "byteOffset", where).value_or(0);
        const std::uint64_t length = required(*v, "byteLength", where, 1);
        // glTF 2.0, 5.11.4: 4 to 252 bytes, a multiple of 4.
        const std::uint64_t stride = integer(*v, "byteStride", where, 4, 252).value_or(0);
        if (stride % 4 != 0) {
            refuse(where + ".byteStride",
                   "is " + std::to_string(stride) + ", must be a multiple of 4");
        }
        if (!io::rangeFits(offset, length, mBufferLength[buffer])) {
            refuse(where, "(byteOffset " + std::to_string(offset) + ", byteLength " +
                              std::to_string(length) + ") runs past the end of buffers[" +
                              std::to_string(buffer) + "] (" +
                              std::to_string(mBufferLength[buffer]) + " bytes)");
        }
        mView.push_back({length, stride});
    }
}

std::uint64_t componentSize(std::uint64_t componentType) {
    switch (componentType) {
    case 5120: // BYTE
    case 5121: // UNSIGNED_BYTE
        return 1;
    case 5122: // SHORT
    case 5123: // UNSIGNED_SHORT
        return 2;
    case 5125: // UNSIGNED_INT
    case 5126: // FLOAT
        return 4;
    default:
        return 0;
    }
}

std::uint64_t componentCount(const std::string& type) {
    static const std::map<std::string, std::uint64_t, std::less<>> kCount = {
        {"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4},
        {"MAT2", 4},   {"MAT3", 9}, {"MAT4", 16}};
    const auto it = kCount.find(type);
    return it == kCount.end() ? 0 : it->second;
}

void DocumentChecker::checkAccessors() {
    std::size_t i = 0;
    for (const json* a : objects(mRoot, "accessors", "accessors")) {
        const std::string where = at("accessors", i++);
        const std::uint64_t offset = integer(*a, "byteOffset", where).value_or(0);
        const std::uint64_t type = required(*a, "componentType", where);
        if (componentSize(type) == 0) {
            refuse(where + ".componentType", "is " + std::to_string(type) +
                                                 ", not one of 5120, 5121, 5122, 5123, 5125, 5126");
        }
        const std::uint64_t count = required(*a, "count", where, 1);
        const json* t = member(*a, "type");
        if (!t) {
            refuse(where + ".type", "is missing");
        }
        const std::uint64_t components = t->is_string() ? componentCount(t->get<std::string>()) : 0;
        if (components == 0) {
            refuse(where + ".type", "is " + describe(*t) + ", not a glTF type");
        }
        if (const json* n = member(*a, "normalized"); n && !n->is_boolean()) {
            refuse(where + ".normalized", "is not true or false");
        }
        const std::uint64_t element = componentSize(type) * components;
        if (const auto view = index(*a, "bufferView", where, "bufferViews")) {
            // glTF 2.0, 3.6.2.4: byteOffset + stride * (count - 1) + element size must lie
            // inside the bufferView; the product wraps around for a count near 2^64 / stride.
            const ViewInfo& v = mView[*view];
            const std::uint64_t stride = v.stride ? v.stride : element;
            const auto span = io::stridedSpan(count, stride, element);
            if (!span || !io::rangeFits(offset, *span, v.length)) {
                refuse(where, "(byteOffset " + std::to_string(offset) + ", count " +
                                  std::to_string(count) + ", stride " + std::to_string(stride) +
                                  ") runs past the end of bufferViews[" + std::to_string(*view) +
                                  "] (" + std::to_string(v.length) + " bytes)");
            }
        } else if (member(*a, "byteOffset") && offset != 0) {
            refuse(where + ".byteOffset", "is set, but the accessor has no bufferView");
        }
        if (const json* sparse = object(*a, "sparse", where + ".sparse")) {
            checkSparse(*sparse, where + ".sparse", count, element);
        }
    }
}

void DocumentChecker::checkSparse(const json& sparse, const std::string& where, std::uint64_t count,
                                  std::uint64_t elementSize) {
    const std::uint64_t n = required(sparse, "count", where, 1, count);
    const json* indices = object(sparse, "indices", where + ".indices");
    const json* values = object(sparse, "values", where + ".values");
    if (!indices) {
        refuse(where + ".indices", "is missing");
    }
    if (!values) {
        refuse(where + ".values", "is missing");
    }
    const auto part = [&](const json& o, const std::string& name, std::uint64_t size) {
        if (!member(o, "bufferView")) {
            refuse(name + ".bufferView", "is missing");
        }
        const std::uint64_t view = *index(o, "bufferView", name, "bufferViews");
        const std::uint64_t offset = integer(o, "byteOffset", name).value_or(0);
        const auto bytes = io::checkedMul(n, size);
        if (!bytes || !io::rangeFits(offset, *bytes, mView[view].length)) {
            refuse(name, "(byteOffset " + std::to_string(offset) + ", " + std::to_string(n) +
                             " x " + std::to_string(size) +
                             " bytes) runs past the end of bufferViews[" + std::to_string(view) +
                             "] (" + std::to_string(mView[view].length) + " bytes)");
        }
    };
    const std::uint64_t indexType = required(*indices, "componentType", where + ".indices");
    if (indexType != 5121 && indexType != 5123 && indexType != 5125) {
        refuse(where + ".indices.componentType",
               "is " + std::to_string(indexType) + ", not one of 5121, 5123, 5125");
    }
    part(*indices, where + ".indices", componentSize(indexType));
    part(*values, where + ".values", elementSize);
}

void DocumentChecker::checkPrimitive(const json& p, const std::string& where) {
    const json* attributes = object(p, "attributes", where + ".attributes");
    if (!attributes) {
        refuse(where + ".attributes", "is missing");
    }
    for (const auto& [name, v] : attributes->items()) {
        indexValue(v, where + ".attributes." + name, "accessors");
    }
    index(p, "indices", where, "accessors");
    index(p, "material", where, "materials");
    integer(p, "mode", where, 0, 6);
    std::size_t k = 0;
    for (const json* target : objects(p, "targets", where + ".targets")) {
        const std::string t = at(where + ".targets", k++);
        for (const auto& [name, v] : target->items()) {
            indexValue(v, t + "." + name, "accessors");
        }
    }
}

void DocumentChecker::checkMeshes() {
    std::size_t i = 0;
    for (const json* m : objects(mRoot, "meshes", "meshes")) {
        const std::string where = at("meshes", i++);
        std::size_t k = 0;
        for (const json* p : objects(*m, "primitives", where + ".primitives")) {
            checkPrimitive(*p, at(where + ".primitives", k++));
        }
    }
}

void DocumentChecker::checkNodes() {
    std::size_t i = 0;
    for (const json* n : objects(mRoot, "nodes", "nodes")) {
        const std::string where = at("nodes", i++);
        index(*n, "camera", where, "cameras");
        index(*n, "mesh", where, "meshes");
        index(*n, "skin", where, "skins");
        if (const json* children = array(*n, "children", where + ".children")) {
            for (std::size_t k = 0; k < children->size(); ++k) {
                indexValue((*children)[k], at(where + ".children", k), "nodes");
            }
        }
        // glTF 2.0, 5.25: a 4x4 matrix is 16 numbers; tinygltf ignores any other count.
        numbers(*n, "matrix", where, 16);
        numbers(*n, "translation", where, 3);
        numbers(*n, "rotation", where, 4);
        numbers(*n, "scale", where, 3);
        const json* ext = object(*n, "extensions", where + ".extensions");
        const std::string lightWhere = where + ".extensions.KHR_lights_punctual";
        const json* light = ext ? object(*ext, "KHR_lights_punctual", lightWhere) : nullptr;
        if (light) {
            index(*light, "light", lightWhere, "lights");
        }
    }
}

void DocumentChecker::checkScenes() {
    if (const json* s = member(mRoot, "scene")) {
        indexValue(*s, "scene", "scenes");
    }
    std::size_t i = 0;
    for (const json* s : objects(mRoot, "scenes", "scenes")) {
        const std::string where = at("scenes", i++);
        if (const json* nodes = array(*s, "nodes", where + ".nodes")) {
            for (std::size_t k = 0; k < nodes->size(); ++k) {
                indexValue((*nodes)[k], at(where + ".nodes", k), "nodes");
            }
        }
    }
}

std::vector<const json*> DocumentChecker::lightList() {
    const json* ext = object(mRoot, "extensions", "extensions");
    const json* punctual =
        ext ? object(*ext, "KHR_lights_punctual", "extensions.KHR_lights_punctual") : nullptr;
    if (!punctual) {
        return {};
    }
    return objects(*punctual, "lights", "extensions.KHR_lights_punctual.lights");
}

void DocumentChecker::checkLights() {
    std::size_t i = 0;
    for (const json* l : lightList()) {
        const std::string where = at("extensions.KHR_lights_punctual.lights", i++);
        const json* type = member(*l, "type");
        if (!type) {
            refuse(where + ".type", "is missing");
        }
        if (!type->is_string() || (*type != "point" && *type != "spot" && *type != "directional")) {
            refuse(where + ".type", "is " + describe(*type) + ", not point, spot or directional");
        }
        numbers(*l, "color", where, 3);
        if (*type != "spot") {
            continue;
        }
        const json* spot = object(*l, "spot", where + ".spot");
        if (!spot) {
            refuse(where + ".spot", "is missing for a spot light");
        }
        // KHR_lights_punctual: 0 <= innerConeAngle < outerConeAngle <= pi / 2.
        const double inner = number(*spot, "innerConeAngle", where + ".spot").value_or(0.0);
        const double outer =
            number(*spot, "outerConeAngle", where + ".spot").value_or(std::numbers::pi / 4.0);
        char line[200];
        if (!(inner >= 0.0) || !(outer <= std::numbers::pi / 2.0) || !(inner < outer)) {
            std::snprintf(line, sizeof(line),
                          "innerConeAngle %.9g and outerConeAngle %.9g: must be 0 <= inner < "
                          "outer <= pi/2",
                          inner, outer);
            refuse(where + ".spot", line);
        }
    }
}

void DocumentChecker::checkCameras() {
    std::size_t i = 0;
    for (const json* c : objects(mRoot, "cameras", "cameras")) {
        const std::string where = at("cameras", i++);
        if (const json* p = object(*c, "perspective", where + ".perspective")) {
            const auto yfov = number(*p, "yfov", where + ".perspective");
            if (!yfov) {
                refuse(where + ".perspective.yfov", "is missing");
            }
            if (!(*yfov > 0.0)) {
                refuse(where + ".perspective.yfov",
                       "is " + describe((*p)["yfov"]) + ", must be > 0");
            }
        }
    }
}

void DocumentChecker::checkSkinsAndAnimations() {
    std::size_t i = 0;
    for (const json* s : objects(mRoot, "skins", "skins")) {
        const std::string where = at("skins", i++);
        index(*s, "inverseBindMatrices", where, "accessors");
        index(*s, "skeleton", where, "nodes");
        if (const json* joints = array(*s, "joints", where + ".joints")) {
            for (std::size_t k = 0; k < joints->size(); ++k) {
                indexValue((*joints)[k], at(where + ".joints", k), "nodes");
            }
        }
    }
    i = 0;
    for (const json* a : objects(mRoot, "animations", "animations")) {
        const std::string where = at("animations", i++);
        const auto samplers = objects(*a, "samplers", where + ".samplers");
        for (std::size_t k = 0; k < samplers.size(); ++k) {
            index(*samplers[k], "input", at(where + ".samplers", k), "accessors");
            index(*samplers[k], "output", at(where + ".samplers", k), "accessors");
        }
        std::size_t k = 0;
        for (const json* c : objects(*a, "channels", where + ".channels")) {
            const std::string w = at(where + ".channels", k++);
            if (const auto s = integer(*c, "sampler", w); s && *s >= samplers.size()) {
                refuse(w + ".sampler", "is " + std::to_string(*s) + ", but " + where + " has " +
                                           std::to_string(samplers.size()) + " samplers");
            }
            if (const json* target = object(*c, "target", w + ".target")) {
                index(*target, "node", w + ".target", "nodes");
            }
        }
    }
}

void DocumentChecker::checkTextureInfo(const json& o, const char* key, const std::string& where) {
    if (const json* info = object(o, key, where + "." + key)) {
        if (!member(*info, "index")) {
            refuse(where + "." + key + ".index", "is missing");
        }
        index(*info, "index", where + "." + key, "textures");
        integer(*info, "texCoord", where + "." + key);
    }
}

void DocumentChecker::checkMaterials() {
    std::size_t i = 0;
    for (const json* m : objects(mRoot, "materials", "materials")) {
        const std::string where = at("materials", i++);
        if (const json* pbr = object(*m, "pbrMetallicRoughness", where + ".pbrMetallicRoughness")) {
            checkTextureInfo(*pbr, "baseColorTexture", where + ".pbrMetallicRoughness");
            checkTextureInfo(*pbr, "metallicRoughnessTexture", where + ".pbrMetallicRoughness");
        }
        for (const char* key : {"normalTexture", "occlusionTexture", "emissiveTexture"}) {
            checkTextureInfo(*m, key, where);
        }
    }
    i = 0;
    for (const json* t : objects(mRoot, "textures", "textures")) {
        const std::string where = at("textures", i++);
        index(*t, "source", where, "images");
        index(*t, "sampler", where, "samplers");
    }
    i = 0;
    for (const json* img : objects(mRoot, "images", "images")) {
        const std::string where = at("images", i++);
        if (const auto view = index(*img, "bufferView", where, "bufferViews")) {
            // The image decoder takes an int length; no image file is allowed more anyway.
            if (mView[*view].length > io::limits::kImageFileBytes) {
                refuse(where, "lies in bufferViews[" + std::to_string(*view) + "] of " +
                                  io::describeBytes(mView[*view].length) + ", over the " +
                                  io::describeBytes(io::limits::kImageFileBytes) +
                                  " limit for one image file");
            }
        }
        if (const json* uri = member(*img, "uri"); uri && !uri->is_string()) {
            refuse(where + ".uri", "is not a string");
        }
    }
}

GltfDocumentFacts DocumentChecker::facts() {
    GltfDocumentFacts f;
    f.sampledImage.assign(mCount["images"], false);
    const json* textures = member(mRoot, "textures");
    const auto sampled = [&](const json* holder, const char* key) {
        const json* info = holder ? member(*holder, key) : nullptr;
        const json* t = info ? member(*info, "index") : nullptr;
        // Extensions' texture indices are not checked above: the loader refuses a bad one.
        if (!t || !t->is_number_unsigned() || !textures ||
            t->get<std::size_t>() >= textures->size()) {
            return;
        }
        const json& texture = (*textures)[t->get<std::size_t>()];
        const json* source = member(texture, "source");
        if (source && source->is_number_unsigned() &&
            source->get<std::size_t>() < f.sampledImage.size()) {
            f.sampledImage[source->get<std::size_t>()] = true;
        }
    };
    for (const json* m : objects(mRoot, "materials", "materials")) {
        const json* pbr = member(*m, "pbrMetallicRoughness");
        sampled(pbr, "baseColorTexture");
        sampled(pbr, "metallicRoughnessTexture");
        sampled(m, "normalTexture");
        sampled(m, "emissiveTexture");
        const json* ext = member(*m, "extensions");
        const json* transmission = ext ? member(*ext, "KHR_materials_transmission") : nullptr;
        if (transmission && transmission->is_object()) {
            sampled(transmission, "transmissionTexture");
        }
    }
    const auto files = [&](const char* list, std::vector<std::string>& out) {
        std::size_t i = 0;
        for (const json* o : objects(mRoot, list, list)) {
            const json* uri = member(*o, "uri");
            if (uri && uri->get<std::string>().rfind("data:", 0) != 0) {
                out.push_back(percentDecoded(uri->get<std::string>()));
                // A %00 ended the name where the system reads it: "quad.bin%00.png" read
                // quad.bin, and a name past the NUL passed the folder check for another file.
                if (out.back().find('\0') != std::string::npos) {
                    refuse(at(list, i) + ".uri", "holds %00 (a NUL), which no file name can");
                }
            }
            ++i;
        }
    };
    files("buffers", f.bufferFiles);
    files("images", f.imageFiles);
    return f;
}

} // namespace

void checkJsonText(std::string_view json, const std::string& file) {
    if (json.size() >= 3 && std::memcmp(json.data(), "\xEF\xBB\xBF", 3) == 0) {
        throw LoadError(file + ": the JSON starts with a byte-order mark, which glTF forbids");
    }
    for (std::size_t i = 0; i < json.size();) {
        if (json[i] == '\0') {
            throw LoadError(file + ": the JSON holds a NUL byte at offset " + std::to_string(i));
        }
        const std::size_t n = utf8Sequence(json, i);
        if (n == 0) {
            throw LoadError(file + ": the JSON is not UTF-8 (byte offset " + std::to_string(i) +
                            ")");
        }
        i += n;
    }
}

std::string messageLine(std::string_view text) {
    constexpr std::size_t kLongRun = 120, kKept = 100;
    std::string line;
    std::size_t i = 0;
    while (i < text.size()) {
        const std::size_t end = std::min(text.find_first_of(" \t\r\n", i), text.size());
        if (end == i) {
            line += ' ';
            ++i;
            continue;
        }
        const std::string_view run = text.substr(i, end - i);
        if (run.size() > kLongRun) {
            line.append(run.substr(0, kKept));
            line += "...(" + std::to_string(run.size()) + " characters)";
        } else {
            line.append(run);
        }
        i = end;
    }
    while (!line.empty() && line.back() == ' ') {
        line.pop_back();
    }
    return line;
}

GltfDocumentFacts validateGltfJson(std::string_view text, const std::string& file) {
    json root;
    try {
        root = json::parse(text.begin(), text.end());
    } catch (const json::exception& e) {
        std::string what = e.what();
        if (const auto at = what.find("] "); at != std::string::npos) {
            what = what.substr(at + 2);
        }
        throw LoadError(file + ": not valid JSON (" + messageLine(what) + ")");
    }
    return DocumentChecker(root, file).check();
}

GlbLayout glbLayout(std::string_view bytes, const std::string& file) {
    const auto u32 = [&](std::uint64_t offset) {
        std::uint32_t v = 0;
        std::memcpy(&v, bytes.data() + offset, 4); // little-endian, like the GLB
        return std::uint64_t{v};
    };
    const auto fail = [&](const std::string& why) { throw LoadError(file + ": " + why); };
    if (bytes.size() < 12 || u32(0) != 0x46546C67u) {
        fail("not a GLB (no \"glTF\" header)");
    }
    // glTF 2.0, 4.4.2: version 2; version 1 is the old glTF 1.0 binary extension.
    if (u32(4) != 2) {
        fail("GLB header version is " + std::to_string(u32(4)) + ", must be 2");
    }
    const std::uint64_t length = u32(8);
    if (length > bytes.size()) {
        fail("GLB header length is " + std::to_string(length) + " bytes, but the file has " +
             std::to_string(bytes.size()) + " (truncated?)");
    }
    // Every chunk: an 8-byte header (length, type), then its data, inside `length`.
    GlbLayout out;
    std::uint64_t offset = 12;
    for (int chunk = 0; offset < length; ++chunk) {
        const std::string name = "GLB chunk " + std::to_string(chunk);
        if (!io::rangeFits(offset, 8, length)) {
            fail(name + " header runs past the GLB length");
        }
        const std::uint64_t chunkLength = u32(offset), type = u32(offset + 4);
        if (!io::rangeFits(offset + 8, chunkLength, length)) {
            fail(name + " length " + std::to_string(chunkLength) + " at byte " +
                 std::to_string(offset) + " runs past the GLB length " + std::to_string(length));
        }
        if (chunk == 0) {
            if (type != 0x4E4F534Au) {
                fail("GLB chunk 0 is not JSON");
            }
            if (chunkLength == 0) {
                fail("GLB JSON chunk is empty");
            }
            out = {offset + 8, chunkLength};
        }
        offset += 8 + chunkLength; // cannot wrap: both lie inside `length` (< 2^32)
    }
    if (out.jsonLength == 0) {
        fail("GLB has no JSON chunk");
    }
    return out;
}

namespace {

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof(text), "%g", v);
    return text;
}

} // namespace

void checkSamplerTimes(std::span<const float> times, bool cubic, const std::string& where) {
    if (times.empty() || (cubic && times.size() < 2)) {
        throw LoadError(where + ": input has " + std::to_string(times.size()) + " keys, " +
                        (cubic ? "CUBICSPLINE needs at least 2" : "needs at least 1"));
    }
    for (std::size_t k = 0; k < times.size(); ++k) {
        const std::string key = " at key " + std::to_string(k);
        if (!std::isfinite(times[k])) {
            throw LoadError(where + ": input time is not a finite number" + key);
        }
        if (times[k] < 0.0f) {
            throw LoadError(where + ": input time " + number(times[k]) + " is negative" + key);
        }
        if (k > 0 && !(times[k] > times[k - 1])) {
            throw LoadError(where + ": input times not increasing" + key + " (" +
                            number(times[k - 1]) + " then " + number(times[k]) + ")");
        }
    }
}

void checkSamplerValues(std::span<const float> values, std::size_t components,
                        const std::string& where) {
    // The loader's limit on coordinates: keys beyond it would carry geometry past what the BVH
    // can bound in floats.
    constexpr float kLimit = 1e12f;
    for (std::size_t i = 0; i < values.size(); ++i) {
        const std::string element =
            " at element " + std::to_string(i / std::max<std::size_t>(components, 1));
        if (!std::isfinite(values[i])) {
            throw LoadError(where + ": output value is not a finite number" + element);
        }
        if (std::abs(values[i]) > kLimit) {
            throw LoadError(where + ": output value " + number(values[i]) + " is outside +-1e12" +
                            element);
        }
    }
}

void checkSamplerCount(std::size_t outputElements, std::size_t keys, std::size_t morphTargets,
                       bool cubic, const std::string& where) {
    const std::size_t expected = keys * std::max<std::size_t>(morphTargets, 1) * (cubic ? 3 : 1);
    if (outputElements == expected) return;
    std::string why = std::to_string(keys) + " keys";
    if (morphTargets > 0) why += " x " + std::to_string(morphTargets) + " morph targets";
    if (cubic) why += " x 3 (CUBICSPLINE: in-tangent, value, out-tangent)";
    throw LoadError(where + ": output has " + std::to_string(outputElements) +
                    " elements, expected " + std::to_string(expected) + " (" + why + ")");
}

} // namespace gt::scene
