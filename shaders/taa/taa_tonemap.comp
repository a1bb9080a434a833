#version 460
// Pass `taa` (taa.comp) that also writes its output tone-mapped (taa.glsl, TAA_TONEMAP).
#extension GL_GOOGLE_include_directive : require
#define TAA_TONEMAP 1
#include "taa.glsl"
