#pragma once
// Sizes and offsets read from a file are attacker-chosen 64-bit numbers: `offset + length` and
// `count * stride` wrap around, and a bounds check written with them passes for a range that
// starts before or ends far past the buffer. Every such sum and product in gazetrace goes through
// these helpers, which report the wrap instead of producing a small number.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

namespace gt::io {

[[nodiscard]] constexpr std::optional<std::uint64_t> checkedAdd(std::uint64_t a,
                                                                std::uint64_t b) noexcept {
    std::uint64_t r = 0;
    if (__builtin_add_overflow(a, b, &r)) return std::nullopt;
    return r;
}

[[nodiscard]] constexpr std::optional<std::uint64_t> checkedMul(std::uint64_t a,
                                                                std::uint64_t b) noexcept {
    std::uint64_t r = 0;
    if (__builtin_mul_overflow(a, b, &r)) return std::nullopt;
    return r;
}

// True when the byte range [offset, offset + length) lies inside a block of `size` bytes, with
// no wrap-around anywhere.
[[nodiscard]] constexpr bool rangeFits(std::uint64_t offset, std::uint64_t length,
                                       std::uint64_t size) noexcept {
    return offset <= size && length <= size - offset;
}

// The span an element array covers: the last element starts at (count - 1) * stride and is
// elementSize bytes long (a stride larger than the element leaves no bytes after the last one).
// nullopt when any step wraps; 0 for count 0.
[[nodiscard]] constexpr std::optional<std::uint64_t>
stridedSpan(std::uint64_t count, std::uint64_t stride, std::uint64_t elementSize) noexcept {
    if (count == 0) return std::uint64_t{0};
    const auto last = checkedMul(count - 1, stride);
    if (!last) return std::nullopt;
    return checkedAdd(*last, elementSize);
}

// A signed number read from a file as a size or an offset: negative values are refused, not
// read as 0 or wrapped to 2^64 - n.
[[nodiscard]] constexpr std::optional<std::uint64_t> nonNegative(std::int64_t v) noexcept {
    if (v < 0) return std::nullopt;
    return static_cast<std::uint64_t>(v);
}

} // namespace gt::io
