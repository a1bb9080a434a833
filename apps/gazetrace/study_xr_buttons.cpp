#include "study_xr_buttons.hpp"

#include <algorithm>
#include <array>

namespace gt::app {

namespace {

using study::Response;

// Each button's answers, the first the phase accepts winning. No procedure accepts two of one
// button's answers at once (design.hpp's procedures: First/Second, Yes/No, First/Second/Same,
// Up/Down/Same, Up/Down/Reference/Accept).
constexpr std::array<std::array<std::optional<Response>, 3>, 4> kAnswers = {{
    {Response::First, Response::Yes, Response::Up},
    {Response::Second, Response::No, Response::Down},
    {Response::Same, Response::Reference, std::nullopt},
    {Response::Accept, std::nullopt, std::nullopt},
}};

constexpr std::array<const char*, 4> kButtonNames = {"left trigger", "right trigger",
                                                     "A/X (trackpad)", "B/Y (menu)"};

bool takes(std::span<const Response> accepted, Response r) {
    return std::find(accepted.begin(), accepted.end(), r) != accepted.end();
}

} // namespace

std::optional<Response> responseOfButton(uint32_t button, std::span<const Response> accepted) {
    if (button >= kAnswers.size()) {
        return std::nullopt;
    }
    // Instructions and breaks: any button goes on.
    if (takes(accepted, Response::Continue)) {
        return Response::Continue;
    }
    for (const std::optional<Response>& r : kAnswers[button]) {
        if (r && takes(accepted, *r)) {
            return r;
        }
    }
    return std::nullopt;
}

std::string buttonPrompt(std::span<const Response> accepted) {
    if (takes(accepted, Response::Continue)) {
        return "any button: continue";
    }
    std::string prompt;
    for (uint32_t b = 0; b < kAnswers.size(); ++b) {
        if (const auto r = responseOfButton(b, accepted)) {
            if (!prompt.empty()) {
                prompt += "  ";
            }
            prompt += std::string(kButtonNames[b]) + ": " + study::responseName(*r);
        }
    }
    return prompt;
}

} // namespace gt::app
