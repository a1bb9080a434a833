#pragma once
// Error policy: unrecoverable failures and contract violations at API
// boundaries throw a gt::Error subclass carrying context; the app boundary catches and prints
// one line. Vulkan calls are checked in every build type through GT_VK_CHECK.
#include <stdexcept>
#include <string>

#include <vulkan/vulkan.h>

namespace gt {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A Vulkan call returned a failure code.
class VulkanError : public Error {
public:
    VulkanError(VkResult result, const char* expr, const char* file, int line);
    [[nodiscard]] VkResult result() const noexcept { return mResult; }

private:
    VkResult mResult;
};

// The render graph was declared in a way that cannot be compiled (cycle, missing producer...).
class GraphError : public Error {
public:
    using Error::Error;
};

// A file could not be loaded: the message names the file and the problem.
class LoadError : public Error {
public:
    using Error::Error;
};

// A command-line or API argument is out of range.
class ArgumentError : public Error {
public:
    using Error::Error;
};

[[nodiscard]] const char* toString(VkResult result) noexcept;

} // namespace gt

#define GT_VK_CHECK(expr)                                                                          \
    do {                                                                                           \
        const VkResult gtVkResult_ = (expr);                                                       \
        if (gtVkResult_ != VK_SUCCESS)                                                             \
            throw ::gt::VulkanError(gtVkResult_, #expr, __FILE__, __LINE__);                       \
    } while (false)
