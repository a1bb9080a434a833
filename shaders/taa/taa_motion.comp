#version 460
// Pass `taa` in a scene that moves: history reprojected with each pixel's motion and rejected
// where its surface or shadow changed (taa.glsl, TAA_MOTION).
#extension GL_GOOGLE_include_directive : require
#define TAA_MOTION 1
#include "taa.glsl"
