#version 460
// Pass `taa` for a method that reports how directly each pixel was sampled this frame
// (kBindingSupport): on a still view each frame counts by it.
#extension GL_GOOGLE_include_directive : require
#define TAA_SUPPORT 1
#include "taa.glsl"
