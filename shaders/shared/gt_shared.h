// Shared between GLSL and C++ (Falcor's host/device-shared idea): in C++ these are plain
// structs and constants in gt::shaders; in GLSL the same declarations compile as GLSL.
#ifndef GT_SHARED_H
#define GT_SHARED_H
#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
#define GT_NAMESPACE_BEGIN(name)                                                                   \
    namespace gt::shaders::name {                                                                  \
    using uint = uint32_t;                                                                         \
    using vec4 = glm::vec4;                                                                        \
    using uvec4 = glm::uvec4;                                                                      \
    using vec2 = glm::vec2;
#define GT_NAMESPACE_END }
#define GT_CONST inline constexpr uint32_t
#define GT_CONSTF inline constexpr float
#else
#define GT_NAMESPACE_BEGIN(name)
#define GT_NAMESPACE_END
#define GT_CONST const uint
#define GT_CONSTF const float
#endif
#endif
