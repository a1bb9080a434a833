#version 460
// Pass `edge_rays` for a reconstruction that reports each pixel's support (edge_rays.glsl).
#extension GL_GOOGLE_include_directive : require
#define EDGE_RAYS_SUPPORT 1
#include "edge_rays.glsl"
