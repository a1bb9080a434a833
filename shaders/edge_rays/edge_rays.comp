#version 460
// Pass `edge_rays` for a reconstruction without a support image (edge_rays.glsl).
#extension GL_GOOGLE_include_directive : require
#include "edge_rays.glsl"
