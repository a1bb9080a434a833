// Pass `layers`: eccentricity layers (Guenter et al. 2012, section 4): each layer traced
// as a pinhole grid over its own sub-frustum, then all resampled and blended on the display grid.
#ifndef LAYERS_SHARED_H
#define LAYERS_SHARED_H
#include "trace_shared.h"

GT_NAMESPACE_BEGIN(layers)

// layers.trace: after the 9 scene bindings.
GT_CONST kBindingTraceOutput = 9; // image2D rgba32f: radiance, a = first-hit distance
// image2D rgba32f, in a scene that moves: the first hit's motion of each layer pixel's first
// ray (shaders/common/motion.glsl); unwritten otherwise
GT_CONST kBindingTraceMotion = 10;
GT_CONST kGroupSizeX = 8;
GT_CONST kGroupSizeY = 8;

struct LayerTracePush {
    vec4 origin; // the layer's camera, as trace::CameraPush (its frustum already jittered)
    vec4 forward;
    vec4 right;
    vec4 up;
    uvec4 params; // x = width, y = height, z = rays per layer pixel, w = geometric LOD level
};

// layers.compose: the layers inner first; slots past the layer count repeat the outer layer.
GT_CONST kMaxLayers = 4;
GT_CONST kBindingLayer0 = 0; // image2D rgba32f, one binding per layer
GT_CONST kBindingComposeOutput = 4;

struct LayerComposePush {
    vec4 gaze; // xy = gaze (display pixels, centres at integers), z unused (the layer count is
               // the pipeline's specialisation constant), w = the transition's share of a
               // layer's radius (0.4, Figure 3)
    // Per layer: xy = display position of the layer grid's top-left corner (pixel edges, this
    // frame's jitter included), z = pitch (display pixels per layer pixel, s_i), w = radius in
    // display pixels where the layer's blend weight reaches 0 (unused for the outer layer).
    vec4 layer[kMaxLayers];
};

GT_NAMESPACE_END
#endif
