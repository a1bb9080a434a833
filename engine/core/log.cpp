#include "core/log.hpp"

#include <atomic>
#include <cstdio>

namespace gt::log {
namespace {
std::atomic<Level> gLevel{Level::Info};
}

void setLevel(Level level) noexcept {
    gLevel = level;
}
bool enabled(Level level) noexcept {
    return level >= gLevel.load();
}

void write(Level level, std::string_view message) noexcept {
    if (!enabled(level)) return;
    const char* tag = level == Level::Error ? "error: " : level == Level::Warn ? "warning: " : "";
    std::fprintf(stderr, "gazetrace: %s%.*s\n", tag, static_cast<int>(message.size()),
                 message.data());
}

} // namespace gt::log
