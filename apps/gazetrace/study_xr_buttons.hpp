#pragma once
// The controller buttons of `gazetrace study --display xr` as a study's answers. xr/ reports
// which of its four buttons was pressed (response_actions.hpp: 0 the left hand's trigger, 1 the
// right hand's, 2 the lower face button, 3 the upper one or menu); here they become the answer the
// current phase accepts, so a participant keeps one rule across procedures: the left hand for
// the first interval (yes, up), the right hand for the second (no, down), the face buttons for
// "same" or the reference (2) and the slider's accept (3), and any button to go on after
// instructions or a break.
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "session.hpp"

namespace gt::app {

// The answer `button` gives where `accepted` are taken, or empty when it gives none there.
[[nodiscard]] std::optional<study::Response>
responseOfButton(uint32_t button, std::span<const study::Response> accepted);

// "left trigger: first  right trigger: second": what each button answers now, for the log and
// the experimenter's instructions.
[[nodiscard]] std::string buttonPrompt(std::span<const study::Response> accepted);

} // namespace gt::app
