#include "view.hpp"

namespace gt::render {

shaders::trace::CameraPush View::cameraPush() const {
    if (frustum) {
        return trace::cameraPush(camera, *frustum);
    }
    return trace::cameraPush(camera, static_cast<float>(width) / static_cast<float>(height));
}

} // namespace gt::render
