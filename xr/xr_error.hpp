#pragma once
// OpenXR failures as gazetrace errors: a typed exception carrying the call and its XrResult,
// thrown by GT_XR_CHECK, caught at the app boundary and printed as one line.
#include <string>

#include "core/error.hpp"
#include "openxr.hpp"

namespace gt::xr {

class XrError : public Error {
public:
    XrError(XrResult result, const std::string& call);
    XrError(XrResult result, const std::string& call, const std::string& what);
    [[nodiscard]] XrResult result() const noexcept { return mResult; }

private:
    XrResult mResult;
};

// "XR_ERROR_SESSION_LOST" for a code the headers know, else the number.
[[nodiscard]] std::string resultName(XrResult result);

// A result that means the runtime is gone: its service stopped, the instance or session lost.
[[nodiscard]] bool runtimeGone(XrResult result) noexcept;

} // namespace gt::xr

#define GT_XR_CHECK(expr)                                                                          \
    do {                                                                                           \
        const XrResult gtXrResult_ = (expr);                                                       \
        if (XR_FAILED(gtXrResult_)) throw ::gt::xr::XrError(gtXrResult_, #expr);                   \
    } while (false)
