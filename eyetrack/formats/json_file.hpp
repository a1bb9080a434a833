#pragma once
// Reading a JSON file the tracker was given (a calibration, camera intrinsics): one place for the
// checks and the one-line errors that name the file, and a typed reader that names the field.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "error.hpp"
#include "input_file.hpp"
#include "limits.hpp"

namespace gt::eyetrack {

// `kind` names what the file should be ("calibration"). Throws FormatError "KIND FILE: why" for a
// folder, a FIFO or device, an oversized file, or text that is not exactly one JSON value
// (whitespace may follow it, nothing else: a calibration with a second document or stray text
// appended is damaged, not one to read the first half of).
[[nodiscard]] inline nlohmann::json readJsonFile(const std::filesystem::path& file,
                                                 const std::string& kind) {
    const std::string what = kind + " " + file.string();
    std::string text;
    try {
        text = io::readInputFile(file, io::limits::kJsonDocumentBytes);
    } catch (const io::InputError& e) {
        throw FormatError(kind + " " + e.what());
    }
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        // The byte where parsing stopped, not nlohmann's own wording.
        throw FormatError(what + ": not valid JSON (at byte " + std::to_string(e.byte) + ")");
    } catch (const nlohmann::json::exception&) {
        throw FormatError(what + ": not valid JSON (a number out of range)");
    }
}

// The typed fields of one JSON object. Every error is one FormatError "WHAT: "PREFIXKEY" why",
// naming the field in the file; no nlohmann exception escapes.
class JsonFields {
public:
    // `what` is "calibration FILE"; `prefix` names the object inside the file ("display.").
    JsonFields(const nlohmann::json& object, std::string what, std::string prefix = "")
        : mObject(object), mWhat(std::move(what)), mPrefix(std::move(prefix)) {
        if (!mObject.is_object()) {
            throw FormatError(mWhat + ": " +
                              (mPrefix.empty() ? std::string("not a JSON object")
                                               : "\"" + mPrefix.substr(0, mPrefix.size() - 1) +
                                                     "\" is not a JSON object"));
        }
    }

    [[nodiscard]] bool has(const char* key) const { return mObject.contains(key); }

    [[nodiscard]] const nlohmann::json& at(const char* key) const {
        const auto it = mObject.find(key);
        if (it == mObject.end()) throw bad(key, "is missing");
        return *it;
    }

    // A finite number within [lo, hi].
    [[nodiscard]] double number(const char* key, double lo, double hi) const {
        return checkedNumber(at(key), key, lo, hi);
    }
    [[nodiscard]] double number(const char* key, double lo, double hi, double fallback) const {
        return has(key) ? number(key, lo, hi) : fallback;
    }

    // An integer within [lo, hi] (a real such as 2.5 or 1e300 is refused, never cast).
    [[nodiscard]] std::int64_t integer(const char* key, std::int64_t lo, std::int64_t hi) const {
        const nlohmann::json& v = at(key);
        std::optional<std::int64_t> i;
        if (v.is_number_unsigned()) {
            const auto u = v.get<std::uint64_t>();
            if (u <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
                i = static_cast<std::int64_t>(u);
        } else if (v.is_number_integer()) {
            i = v.get<std::int64_t>();
        } else {
            throw bad(key, "is not an integer");
        }
        if (!i || *i < lo || *i > hi)
            throw bad(key, "is not in " + std::to_string(lo) + ".." + std::to_string(hi));
        return *i;
    }

    [[nodiscard]] std::string text(const char* key) const {
        const nlohmann::json& v = at(key);
        if (!v.is_string()) throw bad(key, "is not a string");
        return v.get<std::string>();
    }

    // An array of exactly `count` finite numbers within [lo, hi].
    [[nodiscard]] std::vector<double> numbers(const char* key, std::size_t count, double lo,
                                              double hi) const {
        const nlohmann::json& v = at(key);
        if (!v.is_array() || v.size() != count)
            throw bad(key, "must hold " + std::to_string(count) + " numbers");
        std::vector<double> out;
        for (std::size_t i = 0; i < count; ++i)
            out.push_back(checkedNumber(v[i], key, lo, hi));
        return out;
    }

    [[nodiscard]] FormatError bad(const char* key, const std::string& why) const {
        return FormatError(mWhat + ": \"" + mPrefix + key + "\" " + why);
    }

private:
    static std::string range(double lo, double hi) {
        std::ostringstream s;
        s << lo << ".." << hi;
        return s.str();
    }

    double checkedNumber(const nlohmann::json& v, const char* key, double lo, double hi) const {
        if (!v.is_number()) throw bad(key, "is not a number");
        const double x = v.get<double>();
        if (!std::isfinite(x)) throw bad(key, "is not a finite number");
        if (x < lo || x > hi) throw bad(key, "is not in " + range(lo, hi));
        return x;
    }

    const nlohmann::json& mObject;
    std::string mWhat;
    std::string mPrefix;
};

} // namespace gt::eyetrack
