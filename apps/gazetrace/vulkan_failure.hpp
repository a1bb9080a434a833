#pragma once
// A Vulkan failure as the user reads it: out of GPU or host memory and a lost device are the
// ones a user can act on (a smaller image, fewer rays), so they say what to try; the Vulkan
// call and result code stay in the line for a bug report.
#include <string>

#include "core/error.hpp"

namespace gt::app {

[[nodiscard]] std::string vulkanFailureMessage(const VulkanError& error);

} // namespace gt::app
