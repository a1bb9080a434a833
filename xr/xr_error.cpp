#include "xr_error.hpp"

#include <openxr/openxr_reflection.h>

namespace gt::xr {

std::string resultName(XrResult result) {
    switch (result) {
#define GT_XR_RESULT_CASE(name, value)                                                             \
    case name:                                                                                     \
        return #name;
        XR_LIST_ENUM_XrResult(GT_XR_RESULT_CASE)
#undef GT_XR_RESULT_CASE
    default:
        return "XrResult " + std::to_string(static_cast<int>(result));
    }
}

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
    : Error(runtimeGone(result)
                ? "the OpenXR runtime stopped responding (" + callName(call) + ": " +
                      resultName(result) + "); is its service still running?"
                : "OpenXR " + callName(call) + " failed: " + resultName(result)),
      mResult(result) {}

XrError::XrError(XrResult result, const std::string& call, const std::string& what)
    : Error(what + " (" + callName(call) + ": " + resultName(result) + ")"), mResult(result) {}

} // namespace gt::xr
