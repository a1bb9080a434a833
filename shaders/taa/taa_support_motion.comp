#version 460
// Pass `taa` in a scene that moves, for a method that reports how directly each pixel was
// sampled (taa.glsl, TAA_SUPPORT and TAA_MOTION).
#extension GL_GOOGLE_include_directive : require
#define TAA_SUPPORT 1
#define TAA_MOTION 1
#include "taa.glsl"
