#pragma once
// Minimal levelled logging to stderr; stdout is reserved for machine-readable output (--json).
#include <string_view>

namespace gt::log {

enum class Level { Debug, Info, Warn, Error, Quiet };

void setLevel(Level level) noexcept;
[[nodiscard]] bool enabled(Level level) noexcept;
void write(Level level, std::string_view message) noexcept;

inline void info(std::string_view m) noexcept {
    write(Level::Info, m);
}
inline void warn(std::string_view m) noexcept {
    write(Level::Warn, m);
}
inline void error(std::string_view m) noexcept {
    write(Level::Error, m);
}
inline void debug(std::string_view m) noexcept {
    write(Level::Debug, m);
}

} // namespace gt::log
