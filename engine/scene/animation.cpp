#include "scene/animation.hpp"

#include "core/error.hpp"

namespace gt::scene {

AnimationChoice chooseAnimation(const Rig& /*rig*/, const std::string& nameOrIndex) {
    if (nameOrIndex == "all") return {};
    if (nameOrIndex == "none") return {AnimationChoice::Kind::None, 0};
    throw Error("animation: not implemented");
}

Pose evaluatePose(const Rig& rig, const AnimationChoice& /*playing*/, double seconds) {
    Pose p;
    p.seconds = seconds;
    p.world.assign(rig.nodes.size(), glm::mat4(1.0f));
    p.weights.resize(rig.nodes.size());
    return p;
}

void sampleAnimation(const AnimationSampler& /*sampler*/, AnimatedPath /*path*/, float /*t*/,
                     std::span<float> /*out*/) {
    throw Error("animation: not implemented");
}

bool deforms(const Rig& rig, const MeshInstance& instance) noexcept {
    return instance.skin >= 0 || !rig.meshes[instance.mesh].targets.empty();
}

glm::mat4 instanceTransform(const Rig& /*rig*/, const MeshInstance& instance, const Pose& pose) {
    return instance.skin >= 0 ? glm::mat4(1.0f) : pose.world[instance.node];
}

void deformInstance(const Rig& rig, const MeshInstance& instance, const Pose& /*pose*/,
                    std::vector<Vertex>& out) {
    out = rig.meshes[instance.mesh].vertices;
}

} // namespace gt::scene
