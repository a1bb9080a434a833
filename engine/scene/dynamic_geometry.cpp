#include "scene/dynamic_geometry.hpp"

#include "core/error.hpp"

namespace gt::scene {

DynamicGeometry::DynamicGeometry(std::shared_ptr<const Rig> rig, AnimationChoice playing,
                                 double seconds)
    : mRig(std::move(rig)), mPlaying(playing) {
    buildAll(seconds);
}

void DynamicGeometry::buildAll(double /*seconds*/) {
    throw Error("dynamic geometry: not implemented");
}
void DynamicGeometry::rebuildTopLevel() {}
void DynamicGeometry::update(double seconds) {
    buildAll(seconds);
}
void DynamicGeometry::reset(double seconds) {
    buildAll(seconds);
}
std::size_t DynamicGeometry::topLevelCapacity() const noexcept {
    return mInstances.empty() ? 0 : 2 * mInstances.size() - 1;
}
DynamicHit DynamicGeometry::intersect(const Ray& /*ray*/) const {
    return {};
}
bool DynamicGeometry::occluded(const Ray& /*ray*/) const {
    return false;
}
glm::vec3 DynamicGeometry::previousPosition(const DynamicHit& /*hit*/) const {
    return {};
}

} // namespace gt::scene
