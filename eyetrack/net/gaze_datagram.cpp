#include "net/gaze_datagram.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

namespace gt::eyetrack {

namespace {

using Json = nlohmann::json;

// Why a datagram was refused: thrown inside this file only, caught by parseGazeDatagram.
struct Refusal {
    std::string why;
};

// The offset of the first byte that breaks UTF-8 (overlong forms, surrogates and code points
// past U+10FFFF included), or none.
std::optional<std::size_t> firstNonUtf8(std::string_view s) {
    std::size_t i = 0;
    while (i < s.size()) {
        const auto c = static_cast<std::uint8_t>(s[i]);
        std::size_t length = 0;
        std::uint32_t cp = 0, least = 0;
        if (c < 0x80) {
            ++i;
            continue;
        }
        if ((c & 0xE0) == 0xC0) {
            length = 2, cp = c & 0x1Fu, least = 0x80;
        } else if ((c & 0xF0) == 0xE0) {
            length = 3, cp = c & 0x0Fu, least = 0x800;
        } else if ((c & 0xF8) == 0xF0) {
            length = 4, cp = c & 0x07u, least = 0x10000;
        } else {
            return i;
        }
        if (s.size() - i < length) {
            return i;
        }
        for (std::size_t k = 1; k < length; ++k) {
            const auto t = static_cast<std::uint8_t>(s[i + k]);
            if ((t & 0xC0) != 0x80) {
                return i;
            }
            cp = (cp << 6) | (t & 0x3Fu);
        }
        if (cp < least || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) {
            return i;
        }
        i += length;
    }
    return std::nullopt;
}

std::string typeOf(const Json& v) {
    switch (v.type()) {
    case Json::value_t::null:
        return "null";
    case Json::value_t::boolean:
        return "a boolean";
    case Json::value_t::string:
        return "a string";
    case Json::value_t::array:
        return "an array";
    case Json::value_t::object:
        return "an object";
    default:
        return "a number";
    }
}

std::string shown(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

[[noreturn]] void refuse(const std::string& why) {
    throw Refusal{why};
}

[[noreturn]] void wrongType(const char* key, const Json& v, const char* wanted) {
    refuse(std::string("field ") + key + " is " + typeOf(v) + ", must be " + wanted);
}

// The field when the object has it.
const Json* field(const Json& object, const char* key) {
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
}

// A number field within [lo, hi] (open at either end where `open` says so).
std::optional<double> number(const Json& o, const char* key, double lo, double hi,
                             bool open = false) {
    const Json* v = field(o, key);
    if (!v) {
        return std::nullopt;
    }
    if (!v->is_number()) {
        wrongType(key, *v, "a number");
    }
    const double d = v->get<double>();
    const bool inside = open ? (d > lo && d < hi) : (d >= lo && d <= hi);
    if (!std::isfinite(d) || !inside) {
        refuse(std::string("field ") + key + " is " + shown(d) + ", must lie within " +
               (open ? "(" : "[") + shown(lo) + ", " + shown(hi) + (open ? ")" : "]"));
    }
    return d;
}

// One of `names` (a string field), as its index.
template <std::size_t N>
std::optional<std::size_t> oneOf(const Json& o, const char* key, const char* const (&names)[N],
                                 const char* wanted) {
    const Json* v = field(o, key);
    if (!v) {
        return std::nullopt;
    }
    if (!v->is_string()) {
        wrongType(key, *v, "a string");
    }
    const auto& s = v->get_ref<const std::string&>();
    for (std::size_t i = 0; i < N; ++i) {
        if (s == names[i]) {
            return i;
        }
    }
    // Shown escaped and cut short: the bytes are anyone's.
    std::string quoted = Json(s).dump(-1, ' ', true, Json::error_handler_t::replace);
    if (quoted.size() > 40) {
        quoted = quoted.substr(0, 36) + "...\"";
    }
    refuse(std::string("field ") + key + " is " + quoted + ", must be " + wanted);
}

// A pair of number fields: both or neither.
std::optional<cv::Point2d> pair(const Json& o, const char* a, const char* b, double lo, double hi,
                                bool open) {
    const auto first = number(o, a, lo, hi, open);
    const auto second = number(o, b, lo, hi, open);
    if (first.has_value() != second.has_value()) {
        refuse(std::string("field ") + (first ? b : a) + " is missing (" + a + " and " + b +
               " come together)");
    }
    if (!first) {
        return std::nullopt;
    }
    return cv::Point2d(*first, *second);
}

std::optional<cv::Size> screenSize(const Json& o) {
    const Json* v = field(o, "screen");
    if (!v) {
        return std::nullopt;
    }
    if (!v->is_array() || v->size() != 2) {
        if (!v->is_array()) {
            wrongType("screen", *v, "an array [width, height]");
        }
        refuse("field screen has " + std::to_string(v->size()) +
               " entries, must be [width, height]");
    }
    int side[2] = {0, 0};
    for (int i = 0; i < 2; ++i) {
        const Json& s = (*v)[static_cast<std::size_t>(i)];
        if (!s.is_number_integer()) {
            wrongType("screen", s, "[width, height] in whole pixels");
        }
        // A negative integer is no unsigned one.
        if (!s.is_number_unsigned() || s.get<std::uint64_t>() < 1 ||
            s.get<std::uint64_t>() > kMaxGazeScreenSidePx) {
            refuse("field screen is outside 1.." + std::to_string(kMaxGazeScreenSidePx) +
                   " pixels a side");
        }
        side[i] = static_cast<int>(s.get<std::uint64_t>());
    }
    return cv::Size(side[0], side[1]);
}

GazeDatagram fields(const Json& o) {
    if (!o.is_object()) {
        refuse("the datagram is " + typeOf(o) + ", must be a JSON object");
    }
    GazeDatagram d;
    d.tMs = number(o, "t_ms", -kMaxGazeTimeMs, kMaxGazeTimeMs).value_or(0.0);
    static const char* const eyes[] = {"both", "left", "right"};
    d.eye = static_cast<DatagramEye>(
        oneOf(o, "eye", eyes, "\"both\", \"left\" or \"right\"").value_or(0));
    d.anglesDeg = pair(o, "yaw_deg", "pitch_deg", -kMaxGazeAngleDeg, kMaxGazeAngleDeg, true);
    d.screenPx = pair(o, "x", "y", -kMaxGazeScreenPx, kMaxGazeScreenPx, false);
    if (!d.anglesDeg && !d.screenPx) {
        refuse("the datagram has no gaze: it needs x and y, or yaw_deg and pitch_deg");
    }
    d.screen = screenSize(o);
    d.confidence = number(o, "confidence", 0.0, 1.0).value_or(1.0);
    static const char* const events[] = {"fixation", "saccade", "blink"};
    if (const auto e = oneOf(o, "event", events, "\"fixation\", \"saccade\" or \"blink\"")) {
        d.event = static_cast<GazeEvent>(*e);
    }
    if (const Json* s = field(o, "saccade_onset")) {
        if (!s->is_boolean()) {
            wrongType("saccade_onset", *s, "a boolean");
        }
        d.saccadeOnset = s->get<bool>();
    }
    d.vergenceDeg = number(o, "vergence_deg", 0.0, 180.0);
    // Nearly parallel lines of sight fixate very far: any positive distance is one.
    d.fixationCm = number(o, "fixation_cm", 0.0, std::numeric_limits<double>::max(), true);
    return d;
}

} // namespace

DatagramReading parseGazeDatagram(std::string_view bytes) {
    DatagramReading r;
    if (bytes.size() > kMaxGazeDatagramBytes) {
        r.refusal = "the datagram has " + std::to_string(bytes.size()) +
                    " bytes, over the limit of " + std::to_string(kMaxGazeDatagramBytes);
        return r;
    }
    if (const auto at = firstNonUtf8(bytes)) {
        r.refusal = "the datagram is not UTF-8 (at byte offset " + std::to_string(*at) + ")";
        return r;
    }
    Json j;
    try {
        j = Json::parse(bytes.begin(), bytes.end());
    } catch (const Json::parse_error& e) {
        // nlohmann counts bytes from 1.
        r.refusal = "the datagram is not JSON (at byte offset " +
                    std::to_string(e.byte > 0 ? e.byte - 1 : 0) + ")";
        return r;
    } catch (const Json::out_of_range&) {
        r.refusal = "the datagram holds a number beyond a double's range";
        return r;
    }
    try {
        r.datagram = fields(j);
    } catch (const Refusal& refusal) {
        r.refusal = refusal.why;
    }
    return r;
}

} // namespace gt::eyetrack
