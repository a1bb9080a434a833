#version 460
// Pass `taa` (taa_motion.comp) that also writes its output tone-mapped (taa.glsl, TAA_TONEMAP).
#extension GL_GOOGLE_include_directive : require
#define TAA_MOTION 1
#define TAA_TONEMAP 1
#include "taa.glsl"
