// Layouts of the scene as the compute tracer sees it (see engine/trace/gpu_scene.hpp) and the
// push constants of the tracing passes.
#ifndef TRACE_SHARED_H
#define TRACE_SHARED_H
#include "gt_shared.h"

GT_NAMESPACE_BEGIN(trace)

// Descriptor bindings of the scene, identical in every tracing pass (set 0).
GT_CONST kBindingNodes = 0;     // samplerBuffer RGBA32F, 2 texels per BVH node
GT_CONST kBindingTriangles = 1; // samplerBuffer RGBA32F, 3 texels per triangle (v0, e1, e2)
GT_CONST kBindingShading = 2;   // samplerBuffer RGBA32F, 4 texels per triangle
GT_CONST kBindingMaterials = 3; // samplerBuffer RGBA32F, kMaterialTexels per material
GT_CONST kBindingLights = 4;    // samplerBuffer RGBA32F, 4 texels per light
GT_CONST kBindingTexels = 5;    // usamplerBuffer R32UI, packed sRGB RGBA8 texels
// usamplerBuffer RGBA32UI, (offset, width, height, levels): level 0 from `offset`, then each
// level of its mip chain (engine/trace/texture_mips.hpp), halved to at least 1 texel a side.
GT_CONST kBindingTextureInfo = 6;
GT_CONST kBindingSceneUniforms = 7;
GT_CONST kBindingEnvironment = 8; // samplerBuffer RGBA32F, equirectangular, row 0 = up
GT_CONST kSceneBindingCount = 9;

GT_CONST kNodeTexels = 2;
GT_CONST kTriangleTexels = 3;
GT_CONST kShadingTexels = 4;
// Material texels: 0 = base colour factor; 1 = emissive rgb, metallic (-1: unlit);
// 2 = roughness, base colour texture, alpha cutoff, specular weight (KHR_materials_specular's
// specularFactor); 3 = metallic-roughness texture (kNoTexture: none), normal texture, normal
// scale, emissive texture; 4 = transmission, index of refraction, transmission texture,
// 1 for alphaMode BLEND (else 0).
// Texels 2.w, 3 and 4 are read by the path integrator only.
GT_CONST kMaterialTexels = 5;
GT_CONST kLightTexels = 4;
GT_CONST kStackSize = 128; // >= 2 * Bvh::kMaxDepth
GT_CONST kNoTexture = 0xffffffffu;

GT_CONST kLightPoint = 0;
GT_CONST kLightSpot = 1;
GT_CONST kLightDirectional = 2;
// Light texel 3: x = outer cone cosine, y = 1 for a light that stands in for an emissive
// surface of the scene in the direct integrator (path.glsl skips it: the surface itself emits).

// std140-compatible: vec4 members only.
struct SceneUniforms {
    vec4 skyHorizon; // rgb, w = ambient share
    vec4 skyZenith;  // rgb, w = exposure
    vec4 skyGround;  // rgb, w unused
    uvec4 counts;    // x = lights, y = materials, z = textures, w = triangles
    // x = width, y = height (0: none, use the sky gradient); z = the first texel of its
    // importance-sampling tables in the environment table, w = their cells across | down << 16
    // (gpu_scene.cpp, packEnvironmentCdf; read by path.glsl only)
    uvec4 environment;
    // Root node of each geometric LOD level's BVH (0 = full detail, 1.. coarser Catmull-Clark
    // refinements; levels past the scene's last repeat it). A scene without cages has one.
    uvec4 lodRoots;
    // The two-level part of a scene that moves (read only with kDynamic, trace.glsl): x = the
    // top level's root node, y = the first texel of the instance table in the nodes table,
    // z = the instances; w unused. The top level's leaves index instance records.
    uvec4 dynamic;
    // The emissive triangles as the path integrator samples them (gpu_scene.cpp,
    // packEmitters): x = how many, y = the first texel of their alias table in the materials
    // table (one texel each), z = uintBitsToFloat of their total emitted power (luminance of
    // the emissive radiance times area), w = 1 when a material transmits
    // (KHR_materials_transmission or alphaMode BLEND: path.glsl's shadow rays then cross
    // such surfaces).
    uvec4 emitters;
};
GT_CONST kLodLevels = 4;

// Specialisation constant of every tracing shader (trace.glsl's kDynamic): the scene has a
// two-level part (trace::GpuScene::dynamic()). Ids 1 and 2 belong to point_sample's own.
GT_CONST kSpecDynamic = 3;
// Specialisation constants of the integrator (path.glsl; trace::IntegratorSettings): which one,
// its scattering vertices per path, the firefly clamp (a float's bits; 0 = off) and the
// sequence its random decisions draw from.
GT_CONST kSpecIntegrator = 4;
GT_CONST kSpecBounces = 5;
GT_CONST kSpecFireflyClamp = 6;
GT_CONST kSpecSequence = 7;
GT_CONST kSequenceIndependent = 0;
GT_CONST kSequenceSobol = 1;
GT_CONST kIntegratorDirect = 0;
GT_CONST kIntegratorPath = 1;
GT_CONST kIntegratorBruteForce = 2;

// An instance record, kInstanceTexels texels in the nodes table (trace::packInstances):
//   0-2  world-to-object, rows of a 3x4 matrix (object = row . (world, 1))
//   3-5  previous object-to-world, rows of a 3x4 matrix (where the surface was a frame ago)
//   6    x = bottom-level root node, y = its first triangle, z = its first previous triangle
//        (kNoPrevious: rigid, the triangles did not change), w = the rig instance (bits)
//   7    unused
GT_CONST kInstanceTexels = 8;
GT_CONST kNoPrevious = 0xffffffffu;
// gMotion's signature (trace.glsl): surface ids in bits 0-23, shadow mask of lights 0-7 above.
GT_CONST kSurfaceSky = 0;
GT_CONST kSurfaceStatic = 1;
GT_CONST kSurfaceInstance0 = 2; // + the rig instance
GT_CONST kSurfaceIdMask = 0xffffffu;
GT_CONST kShadowMaskShift = 24;

// Camera as a pinhole with an off-axis frustum: dir = normalize(forward + sx * right + sy * up),
// sx = u * tan(yfov / 2) * aspect + centre.x and sy = v * tan(yfov / 2) + centre.y with u, v in
// [-1, 1] across the image (v = 1 at the top). A symmetric frustum has centre (0, 0).
struct CameraPush {
    vec4 origin;  // xyz, w = tan(yfov / 2): half the frustum's height as a tangent
    vec4 forward; // xyz, w = aspect: half width / half height
    vec4 right;   // unit, w = centre.x (tangent)
    vec4 up;      // unit, w = centre.y (tangent)
};

GT_NAMESPACE_END
#endif
