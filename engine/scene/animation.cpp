#include "scene/animation.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>

#include "core/error.hpp"

namespace gt::scene {

namespace {

// --- Samplers (glTF 2.0, Appendix C) ---------------------------------------------------------

// Where t falls among the keys: the key k with times[k] <= t < times[k + 1] and the fraction of
// the way to key k + 1; `clamped` when t is outside the keys (3.11: before the first key the
// first value holds, after the last the last).
struct KeySpan {
    size_t k = 0;
    float u = 0.0f;
    float interval = 0.0f; // times[k + 1] - times[k]
    bool clamped = true;
};

KeySpan findKeys(const std::vector<float>& times, float t) {
    if (times.size() < 2 || !(t > times.front())) return {};
    if (t >= times.back()) return {times.size() - 1, 0.0f, 0.0f, true};
    const auto next = std::upper_bound(times.begin(), times.end(), t);
    const size_t k = static_cast<size_t>(next - times.begin()) - 1;
    const float interval = times[k + 1] - times[k];
    return {k, (t - times[k]) / interval, interval, false};
}

// The key's value: CUBICSPLINE keys store in-tangent, value, out-tangent.
const float* keyValue(const AnimationSampler& s, size_t k) {
    const size_t stride = s.interpolation == Interpolation::CubicSpline ? 3 : 1;
    return s.values.data() + (stride * k + (stride == 3 ? 1 : 0)) * s.components;
}

void normalizeQuat(std::span<float> q) {
    const float len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (len > 0.0f)
        for (float& c : q)
            c /= len;
}

// Appendix C, spherical linear interpolation: along the shorter arc (q and -q are one
// rotation), falling back to a normalised lerp when the keys are nearly parallel.
void slerp(const float* a, const float* b, float u, std::span<float> out) {
    float d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    const float sign = d < 0.0f ? -1.0f : 1.0f;
    d *= sign;
    float wa = 1.0f - u;
    float wb = u;
    if (d < 0.9995f) {
        const float angle = std::acos(d);
        const float s = std::sin(angle);
        wa = std::sin((1.0f - u) * angle) / s;
        wb = std::sin(u * angle) / s;
    }
    for (size_t i = 0; i < 4; ++i)
        out[i] = wa * a[i] + sign * wb * b[i];
    normalizeQuat(out);
}

// Appendix C, cubic Hermite spline: tangents scaled by the key interval t_{k+1} - t_k.
void hermite(const AnimationSampler& s, const KeySpan& span, std::span<float> out) {
    const size_t c = s.components;
    const float* v0 = s.values.data() + (3 * span.k + 1) * c;
    const float* b0 = s.values.data() + (3 * span.k + 2) * c;       // out-tangent of key k
    const float* a1 = s.values.data() + (3 * (span.k + 1) + 0) * c; // in-tangent of key k + 1
    const float* v1 = s.values.data() + (3 * (span.k + 1) + 1) * c;
    const float u = span.u;
    const float u2 = u * u;
    const float u3 = u2 * u;
    const float h00 = 2.0f * u3 - 3.0f * u2 + 1.0f;
    const float h10 = (u3 - 2.0f * u2 + u) * span.interval;
    const float h01 = -2.0f * u3 + 3.0f * u2;
    const float h11 = (u3 - u2) * span.interval;
    for (size_t i = 0; i < c; ++i)
        out[i] = h00 * v0[i] + h10 * b0[i] + h01 * v1[i] + h11 * a1[i];
}

// --- Poses -----------------------------------------------------------------------------------

glm::mat4 composeTrs(const NodeTrs& trs) {
    glm::mat4 m = glm::mat4_cast(trs.rotation);
    m[0] *= trs.scale.x;
    m[1] *= trs.scale.y;
    m[2] *= trs.scale.z;
    m[3] = glm::vec4(trs.translation, 1.0f);
    return m;
}

// Where an animation is at `seconds`: looped over its duration (a duration of 0 holds its first
// key).
float loopedTime(const Animation& animation, double seconds) {
    if (!(animation.duration > 0.0f) || !std::isfinite(seconds)) return 0.0f;
    const double duration = animation.duration;
    double t = std::fmod(seconds, duration);
    if (t < 0.0) t += duration;
    return static_cast<float>(t);
}

void applyAnimation(const Rig& rig, const Animation& animation, double seconds,
                    std::vector<NodeTrs>& local, Pose& pose) {
    const float t = loopedTime(animation, seconds);
    float value[4];
    for (const AnimationChannel& channel : animation.channels) {
        if (channel.sampler >= animation.samplers.size() || channel.node >= rig.nodes.size())
            continue;
        const AnimationSampler& sampler = animation.samplers[channel.sampler];
        NodeTrs& trs = local[channel.node];
        switch (channel.path) {
        case AnimatedPath::Translation:
            sampleAnimation(sampler, channel.path, t, std::span<float>(value, 3));
            trs.translation = {value[0], value[1], value[2]};
            break;
        case AnimatedPath::Rotation:
            sampleAnimation(sampler, channel.path, t, std::span<float>(value, 4));
            trs.rotation = glm::quat(value[3], value[0], value[1], value[2]);
            break;
        case AnimatedPath::Scale:
            sampleAnimation(sampler, channel.path, t, std::span<float>(value, 3));
            trs.scale = {value[0], value[1], value[2]};
            break;
        case AnimatedPath::Weights: {
            std::vector<float>& weights = pose.weights[channel.node];
            weights.resize(sampler.components);
            sampleAnimation(sampler, channel.path, t, weights);
            break;
        }
        }
    }
}

bool plays(const AnimationChoice& playing, size_t index) {
    switch (playing.kind) {
    case AnimationChoice::Kind::All:
        return true;
    case AnimationChoice::Kind::None:
        return false;
    case AnimationChoice::Kind::One:
        return playing.index == index;
    }
    return false;
}

// --- Deformation -----------------------------------------------------------------------------

// glTF 3.7.2.2: position and normal displacements added with the node's weights.
void applyMorphTargets(const RigMesh& mesh, std::span<const float> weights,
                       std::vector<Vertex>& out) {
    bool turned = false;
    const size_t count = std::min(weights.size(), mesh.targets.size());
    for (size_t t = 0; t < count; ++t) {
        const float w = weights[t];
        if (w == 0.0f) continue;
        const MorphTarget& target = mesh.targets[t];
        if (target.positions.size() == out.size())
            for (size_t v = 0; v < out.size(); ++v)
                out[v].position += w * target.positions[v];
        if (target.normals.size() == out.size()) {
            for (size_t v = 0; v < out.size(); ++v)
                out[v].normal += w * target.normals[v];
            turned = true;
        }
    }
    if (!turned) return;
    for (Vertex& v : out) {
        const float len = glm::length(v.normal);
        if (len > 0.0f) v.normal /= len; // a target may cancel a normal: keep it, not a NaN
    }
}

// glTF 3.7.3.3, linear blend skinning: each vertex by the weighted sum of its joints' matrices
// (world[joint] * inverseBind); normals by that matrix's inverse transpose, computed as the
// cofactor matrix (the inverse transpose times the determinant) with the determinant's sign, as
// the normal is renormalised anyway.
void applySkin(const RigMesh& mesh, std::span<const glm::mat4> jointMatrices,
               std::vector<Vertex>& out) {
    for (size_t v = 0; v < out.size(); ++v) {
        const glm::uvec4 joints = mesh.joints[v];
        const glm::vec4 weights = mesh.weights[v];
        glm::mat4 skin(0.0f);
        for (int i = 0; i < 4; ++i) {
            if (weights[i] == 0.0f || joints[i] >= jointMatrices.size()) continue;
            const glm::mat4& joint = jointMatrices[joints[i]];
            skin[0] += weights[i] * joint[0];
            skin[1] += weights[i] * joint[1];
            skin[2] += weights[i] * joint[2];
            skin[3] += weights[i] * joint[3];
        }
        Vertex& vertex = out[v];
        vertex.position = glm::vec3(skin * glm::vec4(vertex.position, 1.0f));
        const glm::vec3 c0(skin[0]);
        const glm::vec3 c1(skin[1]);
        const glm::vec3 c2(skin[2]);
        const glm::vec3 x01 = glm::cross(c0, c1);
        const glm::vec3 cofactor = vertex.normal.x * glm::cross(c1, c2) +
                                   vertex.normal.y * glm::cross(c2, c0) + vertex.normal.z * x01;
        const float len = glm::length(cofactor);
        if (len > 0.0f) vertex.normal = cofactor * (glm::dot(c2, x01) < 0.0f ? -1.0f : 1.0f) / len;
    }
}

std::string quotedNames(const Rig& rig) {
    constexpr size_t kListed = 8;
    std::string list;
    const size_t n = rig.animations.size();
    for (size_t i = 0; i < std::min(n, kListed); ++i) {
        if (i > 0) list += ", ";
        const std::string& name = rig.animations[i].name;
        list += name.empty() ? "(unnamed)" : "\"" + name + "\"";
    }
    if (n > kListed) list += ", and " + std::to_string(n - kListed) + " more";
    return list;
}

} // namespace

AnimationChoice chooseAnimation(const Rig& rig, const std::string& nameOrIndex) {
    if (nameOrIndex == "all") return {};
    if (nameOrIndex == "none") return {AnimationChoice::Kind::None, 0};
    const size_t n = rig.animations.size();
    uint64_t index = 0;
    const char* first = nameOrIndex.data();
    const char* last = first + nameOrIndex.size();
    const auto [end, ec] = std::from_chars(first, last, index);
    if (!nameOrIndex.empty() && ec == std::errc() && end == last && index < n)
        return {AnimationChoice::Kind::One, static_cast<uint32_t>(index)};
    for (size_t i = 0; i < n && !nameOrIndex.empty(); ++i)
        if (rig.animations[i].name == nameOrIndex)
            return {AnimationChoice::Kind::One, static_cast<uint32_t>(i)};
    std::string what = "animation \"" + nameOrIndex + "\": the scene has ";
    if (n == 0) throw ArgumentError(what + "no animations (use all or none)");
    what += std::to_string(n) + (n == 1 ? " animation: " : " animations: ") + quotedNames(rig);
    what += n == 1 ? " (or the index 0)" : " (or an index 0-" + std::to_string(n - 1) + ")";
    throw ArgumentError(what);
}

void sampleAnimation(const AnimationSampler& sampler, AnimatedPath path, float t,
                     std::span<float> out) {
    const size_t c = std::min<size_t>(sampler.components, out.size());
    const KeySpan span = findKeys(sampler.times, t);
    if (span.clamped || sampler.interpolation == Interpolation::Step) {
        std::copy_n(keyValue(sampler, span.k), c, out.begin());
        return;
    }
    if (sampler.interpolation == Interpolation::CubicSpline) {
        hermite(sampler, span, out.first(c));
        if (path == AnimatedPath::Rotation) normalizeQuat(out.first(4));
        return;
    }
    const float* a = keyValue(sampler, span.k);
    const float* b = keyValue(sampler, span.k + 1);
    if (path == AnimatedPath::Rotation) {
        slerp(a, b, span.u, out.first(4));
        return;
    }
    for (size_t i = 0; i < c; ++i)
        out[i] = a[i] + span.u * (b[i] - a[i]);
}

void evaluatePose(const Rig& rig, const AnimationChoice& playing, double seconds, Pose& pose) {
    const size_t n = rig.nodes.size();
    thread_local std::vector<NodeTrs> local;
    local.resize(n);
    pose.seconds = seconds;
    pose.world.resize(n);
    pose.weights.resize(n);
    for (size_t i = 0; i < n; ++i) {
        local[i] = rig.nodes[i].rest;
        pose.weights[i].assign(rig.nodes[i].weights.begin(), rig.nodes[i].weights.end());
    }
    for (size_t a = 0; a < rig.animations.size(); ++a)
        if (plays(playing, a)) applyAnimation(rig, rig.animations[a], seconds, local, pose);
    for (size_t i = 0; i < n; ++i) {
        const RigNode& node = rig.nodes[i];
        const glm::mat4 m = node.hasMatrix ? node.matrix : composeTrs(local[i]);
        pose.world[i] = node.parent >= 0 ? pose.world[static_cast<size_t>(node.parent)] * m : m;
    }
}

Pose evaluatePose(const Rig& rig, const AnimationChoice& playing, double seconds) {
    Pose pose;
    evaluatePose(rig, playing, seconds, pose);
    return pose;
}

bool deforms(const Rig& rig, const MeshInstance& instance) noexcept {
    return instance.skin >= 0 || !rig.meshes[instance.mesh].targets.empty();
}

glm::mat4 instanceTransform(const Rig& /*rig*/, const MeshInstance& instance, const Pose& pose) {
    return instance.skin >= 0 ? glm::mat4(1.0f) : pose.world[instance.node];
}

void deformInstance(const Rig& rig, const MeshInstance& instance, const Pose& pose,
                    std::vector<Vertex>& out) {
    const RigMesh& mesh = rig.meshes[instance.mesh];
    out.assign(mesh.vertices.begin(), mesh.vertices.end());
    if (!mesh.targets.empty() && instance.node < pose.weights.size())
        applyMorphTargets(mesh, pose.weights[instance.node], out);
    if (instance.skin < 0 || mesh.joints.size() != out.size() || mesh.weights.size() != out.size())
        return;
    const Skin& skin = rig.skins[static_cast<size_t>(instance.skin)];
    thread_local std::vector<glm::mat4> jointMatrices;
    jointMatrices.resize(skin.joints.size());
    for (size_t j = 0; j < skin.joints.size(); ++j) {
        const glm::mat4 inverseBind =
            j < skin.inverseBind.size() ? skin.inverseBind[j] : glm::mat4(1.0f);
        jointMatrices[j] = pose.world[skin.joints[j]] * inverseBind;
    }
    applySkin(mesh, jointMatrices, out);
}

} // namespace gt::scene
