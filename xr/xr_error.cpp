#include "xr_error.hpp"

#include <openxr/openxr_reflection.h>

namespace gt::xr {

// One comparison per code the headers list (openxr_reflection.h); the macro list has no
// semicolons, which clang-format cannot lay out.
// clang-format off
std::string resultName(XrResult result) {
#define GT_XR_RESULT_NAME(name, value) if (result == (name)) return #name;
    XR_LIST_ENUM_XrResult(GT_XR_RESULT_NAME)
#undef GT_XR_RESULT_NAME
    return "XrResult " + std::to_string(static_cast<int>(result));
}
// clang-format on

bool runtimeGone(XrResult result) noexcept {
    return result == XR_ERROR_INSTANCE_LOST || result == XR_ERROR_SESSION_LOST ||
           result == XR_ERROR_RUNTIME_FAILURE || result == XR_ERROR_RUNTIME_UNAVAILABLE;
}

namespace {
std::string callName(const std::string& call) {
    // "xrWaitFrame(mSession, &info, &state)" -> "xrWaitFrame"
    const auto paren = call.find('(');
    return paren == std::string::npos ? call : call.substr(0, paren);
}
} // namespace

XrError::XrError(XrResult result, const std::string& call)
    : Error(runtimeGone(result) ? "the OpenXR runtime stopped responding (" + callName(call) +
                                      ": " + resultName(result) + "); is its service still running?"
                                : "OpenXR " + callName(call) + " failed: " + resultName(result)),
      mResult(result) {}

XrError::XrError(XrResult result, const std::string& call, const std::string& what)
    : Error(what + " (" + callName(call) + ": " + resultName(result) + ")"), mResult(result) {}

} // namespace gt::xr
