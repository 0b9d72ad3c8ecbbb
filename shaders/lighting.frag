#version 330 core
// lighting.frag - the deferred lighting pass of softlight: reads the G-buffer, integrates
// image-based lighting (diffuse from irradiance, specular by importance-sampled Monte Carlo,
// specification eq. (1)-(4)) plus point lights, and writes LINEAR radiance (no tone map).
//
// src/shading/lighting.c is a line-by-line C port of this file: same function names, same
// variable names, same order. Change one, change the other (docs/lighting.md).
//
// Draw: one full-screen triangle (or quad); the target is RGBA32F the size of the G-buffer.
// Everything is computed in the ENVIRONMENT's frame: N and V are rotated once by
// uEnvRotation, and since that rotation is about +Z it commutes with the sampling frame
// A = normalize(Z x R) (rotating R about Z rotates A the same way), so dot products, the
// sample pattern and the lookups are those of the world-space formulation.
//
// ---- Uniforms (the host side writes exactly these) ----
// G-buffer, read with texelFetch(sampler, ivec2(gl_FragCoord.xy), 0); window coordinates, row 0
// at the bottom, the size of the target:
//   sampler2D uPosition   .xyz = world-space position (RGB32F or RGBA32F)
//   sampler2D uNormal     .xyz = world-space normal (need not be unit; zero is handled); .w with
//                         uKd's .w: the facet normal, octahedral (facet_normal), read by the
//                         reflection occlusion only when uHasFacet != 0
//   sampler2D uKd         .rgb = linear diffuse albedo Kd
//   sampler2D uKsAlpha    .rgb = Ks (Schlick F0, linear), .a = the lobe parameter alpha: >= 0
//                         the Phong exponent, <= -1 GGX with roughness r = -1 - alpha (a float
//                         target: the sign is kept; src/raster/gbuffer.h)
//   sampler2D uDepth      .r   = window depth; >= 1.0 means "no geometry" (the clear value).
//                               A DEPTH_COMPONENT32F texture with TEXTURE_COMPARE_MODE = NONE
//                               or an R32F copy both work.
//   sampler2D uExtra      .r = occlusion (scales diffuse, specular and env lights, not point
//                         lights), .gba = emission (added last); read only when uHasExtra != 0,
//                         the G-buffer's fifth target for a scene that uses them
//   sampler2D uCone       .xyz = the bent normal (unit, world space), .w = the AO: the ambient
//                         occlusion pass's visibility cone (src/occlusion/gtao.h), read only when
//                         uHasCone != 0 (--ao-radius); then the diffuse, read along
//                         bent_irradiance_dir, is times the occlusion and the specular times the
//                         material's share of it and specular_occlusion
// Environment:
//   sampler2D uEnv        lat-long HDR radiance (RGB32F/RGB16F), full mip chain by
//                         glGenerateMipmap, MIN_FILTER = LINEAR_MIPMAP_LINEAR, MAG_FILTER =
//                         LINEAR, WRAP_S = REPEAT, WRAP_T = CLAMP_TO_EDGE. Upload the image
//                         rows top first (row 0 = top = v 0): then t = v, no flip.
//   float uEnvMaxLod      number of mip levels - 1 (the explicit clamp of every lod)
//   float uLodBase        0.5 * log2(W * H / N), W x H the size of level 0, N the sample count
//   float uSinThetaMin    sin(pi / (2 H)): the distortion factor's floor (centre of row 0)
//   mat3  uEnvRotation    world -> environment directions (rotation about +Z by -rotation)
//   float uEnvIntensity   multiplies every environment radiance (background, diffuse, specular)
//   sampler2D uEnvResidual  what the specular samples read, set up as uEnv: uEnv itself, or, with
//                         env lights, uEnv less them (src/ibl/env_lights.h: each extracted texel
//                         keeps its colour at the luminance of the brightest texel left)
//   int   uEnvLayout      the layout of uEnvResidual: 1 lat-long (as uEnv), 2 octahedral: an S x S
//                         chain uploaded level by level (src/ibl/env_oct.c), MAX_LEVEL = levels - 1,
//                         read with texelFetch (env_oct_bilinear: the fold at the edge is by hand)
//   int   uEnvLightCount  0 .. 64: the environment's brightest texels, summed exactly
//   int   uEnvLightsGGXOnly  1: they are the GGX set's alone; a Phong lobe sums none and its
//                         samples read uEnv (env_lights_of; a scene of both sets' default)
//   vec4  uEnvLightDir[64]       .xyz: the texel's centroid direction (environment space)
//   vec4  uEnvLightRadiance[64]  .rgb: the radiance taken out of it times |integral of w over it|,
//                                .a: the texel's solid angle over that |integral|
//   vec4  uEnvLightTexel[64]     .xyz: the texel's bounds: cos(theta) at its top and bottom
//                                edges, phi at its first edge
//   float uEnvLightSide          the level-0 texel's longest side, max(pi / H, 2 pi / W)
//   float uEnvLightMeridian      every level-0 texel's side along its meridian, pi / H
//   float uEnvLightAzimuth       every level-0 texel's signed width in phi, first edge to last,
//                                -2 pi / W
// Irradiance (diffuse term, Kd / pi * E(N)):
//   int   uIrradianceMethod   0 = SH9 from uSH, otherwise the map uIrradianceMap
//                             (the values of sl_irradiance_method: 0 SH9, 1 BRUTE, 2 MAP,
//                             3 OCT (default), 4 DP)
//   vec3  uSH[9]              SH9 coefficients already multiplied by the cosine lobe's A_l,
//                             order Y00, Y1-1, Y10, Y11, Y2-2, Y2-1, Y20, Y21, Y22
//   sampler2D uIrradianceMap  irradiance E, LINEAR filtering, lod 0: BRUTE and MAP lat-long
//                             (REPEAT s, CLAMP t); OCT an S x S octahedral map, DP a 2S x S
//                             dual-paraboloid map (CLAMP both; S = textureSize(...).y)
// Samples (specification "Building a low-discrepancy list", with a std140-safe layout:
// docs/conventions.md, erratum 5):
//   uniform block HammersleyBlock (std140): float N at offset 0; vec4 hammersley[512] at
//   offset 16, element k/2 holding pair k in .xy (k even) or .zw (k odd). 8208 bytes.
//   The C struct sl_hammersley_block (src/shading/lighting.h) is this layout byte for byte.
// Camera:
//   vec3  uEye            world-space eye position (V = normalize(uEye - P))
//   mat4  uInvViewProj    inverse of projection * view (background directions)
//   vec2  uViewport       target size in pixels (width, height)
// Point lights (no loop runs when uLightCount is 0):
//   int   uLightCount              0 .. 16
//   vec3  uLightPosition[16]       world space
//   vec3  uLightColor[16]          linear RGB
//   float uLightIntensity[16]      radiance added = f * color * intensity / d^2 * max(N.L, 0)
// Shadow maps (src/shadow/shadow.h; drawn by src/gl/shadow_pass.c with shaders/shadow_depth.*),
// each kind its own sampler and layer table:
//   sampler2DArray uShadowCubes    the point lights' cube maps: R32F, six layers per casting
//                                  light (+X, -X, +Y, -Y, +Z, -Z), SHADOW_CUBE_SIZE + 2
//                                  SHADOW_GUARD texels a side, row 0 at the bottom, the view
//                                  depth along the face's axis (+inf: nothing drawn); texelFetch
//   int   uShadowCubeLayer[16]     light i's first layer, -1: light i casts no shadow
//   sampler2DArray uShadowSuns     the env lights' orthographic maps: R32F, layer k map k,
//                                  SHADOW_SUN_SIZE texels a side, row 0 at low y, the depth
//                                  along the map's axis (+inf: nothing drawn); texelFetch
//   int   uShadowSunCount          maps, 0 .. 4 (0: no env light casts)
//   vec3  uShadowSunAxis[4], uShadowSunRight[4], uShadowSunUp[4]   map k's frame (world)
//   vec4  uShadowSunBox[4]         x0, y0 (its box's lowest corner along right, up), sx, sy
//                                  (its extent along them), world units
//   vec2  uShadowSunDepth[4]       sz (the box's extent along the axis), the texel's larger side
//   int   uEnvLightSun[64]         env light j's map, -1: none (never shadowed)
// Sky visibility maps (src/shadow/sky.h, --sky-maps K; drawn by src/gl/shadow_pass.c with
// shaders/shadow_depth.vert and shadow_sun.frag), read by sky_visibility: the diffuse term's
// irradiance (the residual's part: without the env lights' maps' part) times their V; with the
// cone the diffuse is read about N and times the material's occlusion alone (extra.r over the AO)
//   sampler2DArray uSkyMaps        the maps: R32F, layer k map k, SL_SKY_MAP_SIZE texels a side
//                                  (textureSize), row 0 at low y, the depth along the map's axis
//                                  (+inf: nothing drawn); texelFetch
//   int   uSkyMapCount             maps, 0 .. 64 (0: none)
//   vec3  uSkyMapAxis[64], uSkyMapRight[64], uSkyMapUp[64]   map k's frame (world)
//   vec4  uSkyMapBox[64]           x0, y0, sx, sy as uShadowSunBox
//   vec2  uSkyMapDepth[64]         sz, the texel's larger side, as uShadowSunDepth
//   vec3  uSkyMapWeight[64]        m_k: cell k's luminance-weighted direction sum (world)
//   vec3  uSkyCellSite[64]         d_k: cell k's site (environment space; horizon_visible)
//   int   uSkyCellSkySites         the sites on the sky's side of the horizon: the first ones
//   float uSkyCellAngle            a cell's angle, acos(1 - 2 / K): the cap of 4 pi / K steradians
//                                  (lobe_map_factor)
// With the maps, every estimator's samples across the horizon from R are summed apart and times
// the visibility of the map whose cell holds their luminous direction (horizon_visible).
// Options (the values of the C enums in src/shading/lighting.h, already resolved; softlight-gl
// compiles them in as constants, see "Specialization" below):
//   int uLodRule      1 none (lod 0), 2 spec, 3 spec with D/4 (default), 4 GPU Gems 3,
//                     5 pdf (GPU Gems 3's level of p(w) without its +1)
//   int uDistortion   1 = include the lat-long distortion d(theta) in the lod, 0 = not
//   int uGTerm        1 = G/(L.N V.N) = 1/(L.H)^2 (default), 2 = 1
//   int uEstimator    1 = spec eq. (3) (divide by D(H); default), 2 = consistent (divide by p(w)),
//                     3 = microfacet (H drawn from D(H) (N.H), w = reflect(-V, H), divide by p(w)),
//                     4 = split sum (no samples: uSplitSum* below), 5 = MIS (uEnvDist* below),
//                     6 = cv, the split sum as a control variate (specular_cv)
//                     7 = cvmis, the same with mis's samples (specular_cv with mis)
//   int uLodRuleGGX, uDistortionGGX, uEstimatorGGX
//                     the same for the pixels of the GGX set (estimator_of): a scene of both sets
//                     samples its GGX objects otherwise than the Phong ones; else equal to the above
// MIS (uEstimator 5; src/ibl/env_dist.h): per Hammersley pair one sample drawn as the microfacet
// estimator's and one from the environment's luminance, weighed by the power heuristic (the host
// builds HammersleyBlock with (N + 1) / 2 pairs for N samples), radiance read at level 0 of
// uEnvResidual (lat-long only) with texelFetch, the texel that holds the direction:
//   sampler2D uEnvDist        W x H RG32F, NEAREST: .r the conditional CDF of row j at column i,
//                             .g the density (per sr) of directions in texel (i, j)
//   sampler2D uEnvDistMarginal  H x 1 R32F, NEAREST: the CDF of the rows
//   int   uEnvDistShift       log2 of (uEnvResidual's level 0 width / W): the grid is that level
// Split sum (uEstimator 4; src/ibl/prefilter.c, src/shading/splitsum_lut.h):
//   sampler2D uSplitSumPhong, uSplitSumGGX  lat-long chains, level k the environment (what the
//                         samples read) convolved with the lobe of width r = k / uSplitSumMaxLod at
//                         N = V = R; uploaded level by level, LINEAR_MIPMAP_LINEAR, REPEAT s, CLAMP t
//   float uSplitSumMaxLod their level count - 1 (SPLITSUM_LEVELS - 1)
//   sampler2D uSplitSumLut  SPLITSUM_LUT_SIZE x (3 SPLITSUM_LUT_SIZE) RGBA32F, LINEAR, CLAMP: .x = A,
//                         .y = B of the BRDF's albedo Ks A + B over (N.V, r), .z = t, the lookup
//                         direction's factor (splitsum_dir), .w = beta, the control variate's
//                         coefficient, one set per block of rows
//   int   uSplitSumExactLevel  the chains' first exact level: from it on, level k holds the
//                         environment's integral against cv_kernel's kernel (src/ibl/prefilter.c)
//   float uSplitSumKernelNorm[SPLITSUM_SETS * SPLITSUM_LEVELS]  1 / Z of set s's level k at
//                         s SPLITSUM_LEVELS + k (the kernel's normalisation, src/ibl/ibl.h)
//   int uDiffuse, uSpecular, uPointLights   1 = on, 0 = off
//   int uRotate       1 = Cranley-Patterson rotation: every Hammersley pair is offset by the
//                     pixel's pseudo-random vector pixel_rotation() mod 1 (0 = off: the same set
//                     in every pixel)
//   uint uFrame       frame number hashed into that vector: frames 0, 1, 2, ... average to the
//                     converged image (progressive refinement)
// Output: location 0, vec4(linear radiance, a) with a = 1, or vec4(0) where a non-finite value
// was repaired (the host can count pixels with a = 0; the C pass counts them in its stats).

uniform sampler2D uPosition;
uniform sampler2D uNormal;
uniform sampler2D uKd;
uniform sampler2D uKsAlpha;
uniform sampler2D uDepth;
uniform sampler2D uExtra; // .r occlusion, .gba emission: only when uHasExtra (src/raster/gbuffer.h)
uniform sampler2D uCone;  // .xyz bent normal, .w AO: only when uHasCone (src/occlusion/gtao.h)
uniform int uHasCone;
uniform int uHasFacet; // uNormal.w, uKd.w hold the facet normal (src/raster/gbuffer.h sl_gbuffer.facet)
#ifdef SL_SPECIALIZED
const int uHasExtra = SL_HAS_EXTRA;
#else
uniform int uHasExtra;
#endif

uniform sampler2D uEnv;
uniform float uEnvMaxLod;
uniform float uLodBase;
uniform float uSinThetaMin;
uniform mat3 uEnvRotation;
uniform float uEnvIntensity;
uniform sampler2D uEnvResidual;
#ifdef SL_SPECIALIZED
const int uEnvLayout = SL_ENV_LAYOUT;
#else
uniform int uEnvLayout;
#endif

const int MAX_ENV_LIGHTS = 64;
uniform int uEnvLightCount;
#ifdef SL_SPECIALIZED
const int uEnvLightsGGXOnly = SL_ENV_LIGHTS_GGX_ONLY;
#else
uniform int uEnvLightsGGXOnly;
#endif
uniform vec4 uEnvLightDir[MAX_ENV_LIGHTS];
uniform vec4 uEnvLightRadiance[MAX_ENV_LIGHTS];
uniform vec4 uEnvLightTexel[MAX_ENV_LIGHTS];
uniform float uEnvLightSide;
uniform float uEnvLightMeridian;
uniform float uEnvLightAzimuth;

#ifdef SL_SPECIALIZED
const int uIrradianceMethod = SL_IRRADIANCE_METHOD;
#else
uniform int uIrradianceMethod;
#endif
uniform vec3 uSH[9];
uniform sampler2D uIrradianceMap;

layout(std140) uniform HammersleyBlock {
    float N;
    vec4 hammersley[512];
} uHammersley;

uniform vec3 uEye;
uniform mat4 uInvViewProj;
uniform vec2 uViewport;
// the reflection occlusion's ray length (0: off) and the camera's frame: right, up and forward
// unit vectors and the pixels one world unit at view depth 1 spans (src/occlusion/gtao.h)
uniform float uReflectionDistance;
uniform vec3 uViewForward;
uniform vec3 uViewRight;
uniform vec3 uViewUp;
uniform float uPixelsPerUnit;

const int MAX_LIGHTS = 16;
uniform int uLightCount;
uniform vec3 uLightPosition[MAX_LIGHTS];
uniform vec3 uLightColor[MAX_LIGHTS];
uniform float uLightIntensity[MAX_LIGHTS];
uniform sampler2DArray uShadowCubes;
uniform int uShadowCubeLayer[MAX_LIGHTS];
const int SHADOW_SUN_MAX = 4;
uniform sampler2DArray uShadowSuns;
uniform int uShadowSunCount;
uniform vec3 uShadowSunAxis[SHADOW_SUN_MAX];
uniform vec3 uShadowSunRight[SHADOW_SUN_MAX];
uniform vec3 uShadowSunUp[SHADOW_SUN_MAX];
uniform vec4 uShadowSunBox[SHADOW_SUN_MAX];
uniform vec2 uShadowSunDepth[SHADOW_SUN_MAX];
uniform int uEnvLightSun[MAX_ENV_LIGHTS];
uniform int uEnvGlowCount;               // with the env lights' maps, their count
uniform vec4 uEnvGlow[SHADOW_SUN_MAX];   // map k's glow: .xyz its direction (environment space),
                                         // .w the cosine of the cap its samples lie in
const int SKY_MAPS_MAX = 64;
uniform sampler2DArray uSkyMaps;
uniform int uSkyMapCount;
uniform vec3 uSkyMapAxis[SKY_MAPS_MAX];
uniform vec3 uSkyMapRight[SKY_MAPS_MAX];
uniform vec3 uSkyMapUp[SKY_MAPS_MAX];
uniform vec4 uSkyMapBox[SKY_MAPS_MAX];
uniform vec2 uSkyMapDepth[SKY_MAPS_MAX];
uniform vec3 uSkyMapWeight[SKY_MAPS_MAX];
uniform vec3 uSkyCellSite[SKY_MAPS_MAX];
uniform int uSkyCellSkySites;
uniform float uSkyCellAngle;

uniform sampler2D uEnvDist;
uniform sampler2D uEnvDistMarginal;
uniform int uEnvDistShift;

uniform sampler2D uSplitSumPhong;
uniform sampler2D uSplitSumGGX;
uniform sampler2D uSplitSumLut;
uniform float uSplitSumMaxLod;
uniform int uSplitSumExactLevel;
uniform float uSplitSumKernelNorm[18]; // SPLITSUM_SETS * SPLITSUM_LEVELS

uniform uint uFrame;

// ---- Specialization (src/gl/lighting_pass.c) ----
// softlight-gl compiles this file once per combination of the options and scene features it
// uses, with SL_SPECIALIZED and the SL_* values below #defined after the #version line: the
// options become constants, so the compiler drops every branch the scene cannot take. llvmpipe
// runs fragments as SIMD lanes under execution masks and pays for the code of a branch no lane
// takes; the C pass models only what a scene needs, and the GL twin it is measured against must
// too (docs/gl.md "One program per scene"). Without SL_SPECIALIZED this is the general shader
// (what src/shading/lighting.c ports), every option a uniform.
#ifdef SL_SPECIALIZED
const int uLodRule = SL_LOD_RULE;
const int uDistortion = SL_DISTORTION;
const int uGTerm = SL_GTERM;
const int uEstimator = SL_ESTIMATOR;
const int uLodRuleGGX = SL_LOD_RULE_GGX;
const int uDistortionGGX = SL_DISTORTION_GGX;
const int uEstimatorGGX = SL_ESTIMATOR_GGX;
const int uDiffuse = SL_DIFFUSE;
const int uSpecular = SL_SPECULAR;
const int uPointLights = SL_POINT_LIGHTS; // 0 also when the scene has no point light
const int uRotate = SL_ROTATE;
#else
uniform int uLodRule;
uniform int uDistortion;
uniform int uGTerm;
uniform int uEstimator;
uniform int uLodRuleGGX;
uniform int uDistortionGGX;
uniform int uEstimatorGGX;
uniform int uDiffuse;
uniform int uSpecular;
uniform int uPointLights;
uniform int uRotate;
// The scene's features: which microfacet sets its G-buffer holds, whether it has env lights,
// whether a point light has a cube shadow map, whether an env light has an orthographic one,
// whether sky visibility maps are drawn.
#define SL_PHONG 1
#define SL_GGX 1
#define SL_ENV_LIGHTS 1
#define SL_SHADOW_CUBES 1
#define SL_SHADOW_SUNS 1
#define SL_SKY_MAPS 1
#endif

layout(location = 0) out vec4 fragColor;

const float PI = 3.14159265358979;
const int LOD_NONE = 1;
const int LOD_SPEC = 2;
const int LOD_SPEC_D4 = 3;
const int LOD_GEMS = 4;
const int LOD_PDF = 5;
const int GTERM_INV_LH2 = 1;
const int ESTIMATOR_CONSISTENT = 2;
const int ESTIMATOR_MICROFACET = 3;
const int ESTIMATOR_SPLITSUM = 4;
const int ESTIMATOR_MIS = 5;
const int ESTIMATOR_CV = 6;
const int ESTIMATOR_CV_MIS = 7;
const int SPLITSUM_LUT_SIZE = 32;
const int SPLITSUM_SETS = 3;
const int SPLITSUM_LEVELS = 6;
const int SPLITSUM_PHONG_INV_LH2 = 0;
const int SPLITSUM_PHONG_ONE = 1;
const int SPLITSUM_GGX = 2;
const int ENV_LAYOUT_OCT = 2;
const int IRRADIANCE_SH9 = 0;
const int IRRADIANCE_OCT = 3;
const int IRRADIANCE_DP = 4;

// Numerical guards (docs/lighting.md, "Hard cases"):
const float MIN_NDOTV = 0.01;      // normals facing away from the eye are bent to N.V = 0.01
const float MIN_LDOTH = 1e-3;      // floor of L.H in 1/(L.H)^2
const float POLE_EPS = 1e-6;       // |R.xy|^2 below this: Z x R vanishes, use X x R instead
const float TINY = 1e-30;          // floor of pow() and log2() arguments
const float MAX_ALPHA = 1e7;       // alpha beyond this is a mirror to float precision
const float MIN_LIGHT_D2 = 1e-8;   // a light closer than 1e-4 has no defined direction
const float GGX_MIN_A = 1e-4;      // GGX a = max(r^2, 1e-4): r = 0 stays a finite lobe

// The point lights' cube shadow maps (src/shadow/shadow.h, whose constants these are; docs/
// lighting.md "Shadow maps" says why these values):
const int SHADOW_CUBE_SIZE = 512;       // texels along a face's side, inside the guard band
const int SHADOW_GUARD = 3;             // texels of guard band on each side
const float SHADOW_BIAS_CONST = 1.0;    // bias beyond the receiver plane, in texel footprints
const float SHADOW_DEPTH_REL = 2e-4;    // and a share of the stored depth
const float SHADOW_NORMAL_OFFSET = 1.0; // the receiver moved along its normal, in texels, at most
// The env lights' orthographic maps read the same three, in their own texels:
const int SHADOW_SUN_SIZE = 2048;       // texels along a map's side
// The sky visibility maps' lookup (src/shadow/sky.c, whose constants these are), in their texels:
const float SKY_NORMAL_OFFSET = 1.0;    // the receiver moved along its normal
const float SKY_BIAS_CONST = 1.0;       // bias beyond the receiver plane
// A lobe at least this share of a sky map's cell wide takes that map too (lobe_map_factor; the
// C side's SL_LOBE_MAP_SHARE, src/shading/lighting_internal.h):
const float LOBE_MAP_SHARE = 0.5;

// The specification's lat-long map (ported in src/ibl/latlong.c). atan(0, 0) is undefined in
// GLSL, so the poles take phi = 0 explicitly, as C's atan2 does; u = 1 (atan = -pi) folds to 0,
// and z is clamped before acos (a normalised z can round to 1 + 1 ulp).
vec2 sl_dir_to_uv(vec3 d)
{
    float phi = (d.x == 0.0 && d.y == 0.0) ? 0.0 : atan(d.y, d.x);
    float u = 0.5 - phi / (2.0 * PI);
    u = u < 1.0 ? u : u - 1.0;
    u = u >= 0.0 ? u : 0.0;
    float z = min(max(d.z, -1.0), 1.0);
    return vec2(u, acos(z) / PI);
}

// Eq. (4) (ported in src/ibl/latlong.c).
vec3 sl_uv_to_dir(vec2 uv)
{
    float phi = 2.0 * PI * (0.5 - uv.x);
    float theta = PI * uv.y;
    return vec3(cos(phi) * sin(theta), sin(phi) * sin(theta), cos(theta));
}

// D(H) = (alpha + 2) / (2 pi) (N.H)^alpha (brdf.h sl_brdf_D).
float sl_brdf_D(float NdotH, float alpha)
{
    return (alpha + 2.0) / (2.0 * PI) * pow(max(NdotH, TINY), alpha);
}

// G(L, V, H) / ((L.N)(V.N)): 1/(L.H)^2 or 1 (brdf.h sl_brdf_G).
float sl_brdf_G(float LdotH, int gterm)
{
    if (gterm == GTERM_INV_LH2) {
        float LH = max(LdotH, MIN_LDOTH);
        return 1.0 / (LH * LH);
    }
    return 1.0;
}

// Schlick: F = Ks + (1 - Ks)(1 - L.H)^5; 1 - L.H clamped at 0 (L.H rounds above 1).
vec3 sl_brdf_F(vec3 Ks, float LdotH)
{
    float m = max(1.0 - LdotH, 0.0);
    float m2 = m * m;
    return Ks + (vec3(1.0) - Ks) * (m2 * m2 * m);
}

// GGX, the second microfacet set (brdf.h): it replaces D and G; F stays Schlick's. A pixel's
// lobe parameter alpha <= -1 is GGX with roughness r = -1 - alpha, a = max(r^2, GGX_MIN_A).
float sl_ggx_a2(float alpha)
{
    float r = -1.0 - alpha;
    float a = max(r * r, GGX_MIN_A);
    return a * a;
}

// D(H) = a^2 / (pi ((N.H)^2 (a^2 - 1) + 1)^2), the bracket as (1 - (N.H)^2) + (N.H)^2 a^2: in
// float a^2 - 1 is -1 for a^2 < 6e-8, and the literal form then divides by 0 at N.H = 1.
float sl_ggx_D(float NdotH, float a2)
{
    float c2 = NdotH * NdotH;
    float t = max(1.0 - c2, 0.0) + c2 * a2;
    return a2 / (PI * t * t);
}

// G / ((L.N)(V.N)) = 4 Vis, Vis the height-correlated Smith visibility
// 0.5 / ((N.L) sqrt((N.V)^2 (1 - a^2) + a^2) + (N.V) sqrt((N.L)^2 (1 - a^2) + a^2)).
float sl_ggx_G(float NdotL, float NdotV, float a2)
{
    float gv = NdotL * sqrt(NdotV * NdotV * (1.0 - a2) + a2);
    float gl = NdotV * sqrt(NdotL * NdotL * (1.0 - a2) + a2);
    return 2.0 / (gv + gl);
}

// The pixel's microfacet set: GGX for a negative lobe parameter. A program specialized for a
// scene with one set only answers without looking (SL_PHONG, SL_GGX).
bool sl_lobe_is_ggx(float alpha)
{
    return SL_PHONG == 0 || (SL_GGX != 0 && alpha < 0.0);
}

// How a pixel samples the environment, by its lobe set: the GGX set's own uniforms (a scene of
// both sets gives its GGX objects the accurate default, its Phong ones the recipe), which equal
// the frame's where it has none.
int estimator_of(float alpha)
{
    return sl_lobe_is_ggx(alpha) ? uEstimatorGGX : uEstimator;
}
int lod_rule_of(float alpha)
{
    return sl_lobe_is_ggx(alpha) ? uLodRuleGGX : uLodRule;
}
int distortion_of(float alpha)
{
    return sl_lobe_is_ggx(alpha) ? uDistortionGGX : uDistortion;
}
// Whether a lobe sums the env lights, its samples then reading uEnvResidual: every lobe, or with
// uEnvLightsGGXOnly a GGX one alone (a Phong lobe's samples read uEnv, as the recipe's do).
bool env_lights_of(float alpha)
{
    return uEnvLightCount > 0 && (uEnvLightsGGXOnly == 0 || sl_lobe_is_ggx(alpha));
}

// D and G of the pixel's set, by the sign of its lobe parameter (uGTerm is the Phong set's).
float sl_lobe_D(float NdotH, float alpha)
{
    return sl_lobe_is_ggx(alpha) ? sl_ggx_D(NdotH, sl_ggx_a2(alpha)) : sl_brdf_D(NdotH, alpha);
}

float sl_lobe_G(float LdotH, float NdotL, float NdotV, float alpha, int gterm)
{
    return sl_lobe_is_ggx(alpha) ? sl_ggx_G(NdotL, NdotV, sl_ggx_a2(alpha)) : sl_brdf_G(LdotH, gterm);
}

// GGX importance sampling: cos(theta) of a direction drawn with density D(c) c about the axis,
// c = sqrt((1 - xi2) / (1 + (a^2 - 1) xi2)) (the inverse of the CDF of D(c) c), the denominator
// as (1 - xi2) + a^2 xi2 (sl_ggx_D's reason).
float ggx_cos_theta(float xi2, float a2)
{
    return sqrt((1.0 - xi2) / ((1.0 - xi2) + a2 * xi2));
}

// D at that c, from xi2 exactly: c^2 (a^2 - 1) + 1 = a^2 / (1 + (a^2 - 1) xi2), so
// D = (1 + (a^2 - 1) xi2)^2 / (pi a^2).
float ggx_D_of_xi(float xi2, float a2)
{
    float t = (1.0 - xi2) + a2 * xi2;
    return t * t / (PI * a2);
}

// Pair k of the Hammersley set: two pairs per vec4 (std140).
vec2 hammersley_point(int k)
{
    vec4 h = uHammersley.hammersley[k >> 1];
    return ((k & 1) == 0) ? h.xy : h.zw;
}

// Wellons' lowbias32: two multiply-xorshift rounds, full avalanche; 32-bit unsigned arithmetic,
// so C (uint32_t) and GLSL agree bit for bit.
uint hash_u32(uint x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// The pixel's offset in [0, 1)^2 for the Cranley-Patterson rotation: 24 bits of two chained
// hashes of (x, y, uFrame), exact in float. The added constants keep hash(0) = 0 from making
// pixel (0, 0) of frame 0 unrotated and neighbours' components equal.
vec2 pixel_rotation(ivec2 pixel)
{
    uint h = hash_u32(uint(pixel.x) + hash_u32(uint(pixel.y) + hash_u32(uFrame + 0x9e3779b9u)));
    uint h2 = hash_u32(h + 0x68e31da4u);
    return vec2(float(h >> 8), float(h2 >> 8)) * (1.0 / 16777216.0);
}

// Specification steps 2-3: skew (xi1, xi2) to the lobe about +Z,
// (u, v) = (xi1, acos(xi2^(1/(alpha+1))) / pi), then eq. (4). GGX (alpha < 0) draws the same
// structure with its own lobe: cos(theta) = ggx_cos_theta, density D(w.R) (w.R) about R.
vec3 skewed_sample(vec2 xi, float alpha)
{
    float c = sl_lobe_is_ggx(alpha) ? ggx_cos_theta(xi.y, sl_ggx_a2(alpha)) : pow(xi.y, 1.0 / (alpha + 1.0));
    vec2 uv = vec2(xi.x, acos(clamp(c, -1.0, 1.0)) / PI);
    return sl_uv_to_dir(uv);
}

// Density of the drawn direction w: p(w) = (alpha + 1) / (2 pi) (w.R)^alpha, with
// (w.R)^alpha = xi2^(alpha / (alpha + 1)) exactly (w.R = xi2^(1/(alpha+1))); the xi form does not
// underflow at large alpha as pow(w.R, alpha) does. GGX: D(w.R) (w.R), D from xi2 exactly.
float sample_pdf(vec2 xi, float alpha)
{
    if (sl_lobe_is_ggx(alpha)) {
        float a2 = sl_ggx_a2(alpha);
        return ggx_D_of_xi(xi.y, a2) * ggx_cos_theta(xi.y, a2);
    }
    return (alpha + 1.0) / (2.0 * PI) * pow(xi.y, alpha / (alpha + 1.0));
}

// The mip level of one sample (docs/lighting.md "Mip level"). d is the texel's solid angle
// relative to the mean 4 pi / (W H): lat-long (pi/2) sin(theta), floored at row 0's centre;
// octahedral |w|_1^3 / pi (src/ibl/env_oct.c). alpha: the lobe, whose set has its rule.
float mip_level(float alpha, float D, float pdf, vec3 w)
{
    int rule = lod_rule_of(alpha), distortion = distortion_of(alpha);
    if (rule == LOD_NONE)
        return 0.0;
    float d = 1.0;
    if (distortion != 0 && uEnvLayout == ENV_LAYOUT_OCT) {
        float l1 = abs(w.x) + abs(w.y) + abs(w.z);
        d = l1 * l1 * l1 / PI;
    } else if (distortion != 0) {
        d = 0.5 * PI * max(sqrt(max(1.0 - w.z * w.z, 0.0)), uSinThetaMin);
    }
    float lod;
    if (rule == LOD_SPEC)
        lod = uLodBase - 0.5 * log2(max(D * d, TINY));
    else if (rule == LOD_SPEC_D4)
        lod = uLodBase - 0.5 * log2(max(D / 4.0 * d, TINY));
    else if (rule == LOD_GEMS)
        lod = uLodBase - 0.5 * log2(max(4.0 * PI * pdf * d, TINY)) + 1.0;
    else
        lod = uLodBase - 0.5 * log2(max(4.0 * PI * pdf * d, TINY));
    return clamp(lod, 0.0, uEnvMaxLod);
}

// The octahedral chain (src/ibl/texture_lod.h, ported there as sl_oct_dir_to_uv, sl_oct_tap,
// sl_oct_texels_bilinear, sl_oct_lod_clamped): p = w.xy / |w|_1, folded below the equator.
vec2 env_oct_uv(vec3 w)
{
    float a = abs(w.x) + abs(w.y) + abs(w.z);
    float px = w.x / a, py = w.y / a;
    float fx = (1.0 - abs(py)) * (px >= 0.0 ? 1.0 : -1.0);
    float fy = (1.0 - abs(px)) * (py >= 0.0 ? 1.0 : -1.0);
    px = w.z < 0.0 ? fx : px;
    py = w.z < 0.0 ? fy : py;
    return clamp(vec2(px, py) * 0.5 + 0.5, 0.0, 1.0);
}

// A tap past the outer edge reads the texel mirrored across it: the direction beyond the fold.
ivec2 env_oct_tap(int s, ivec2 t)
{
    if (t.x < 0 || t.x >= s) {
        t.x = clamp(t.x, 0, s - 1);
        t.y = s - 1 - t.y;
    }
    if (t.y < 0 || t.y >= s) {
        t.y = clamp(t.y, 0, s - 1);
        t.x = s - 1 - t.x;
    }
    return t;
}

// GL_LINEAR by hand within one level: the four taps through env_oct_tap. The level's size is
// level 0's shifted, not textureSize(uEnvResidual, level): on llvmpipe that query, given a level
// that differs between the fragments it runs together (each sample picks its own), gives wrong
// sizes and the taps land on the wrong texels (measured, docs/gl.md "Octahedral chain").
vec3 env_oct_bilinear(int level, vec2 uv)
{
    int s = textureSize(uEnvResidual, 0).x >> level;
    vec2 xy = uv * float(s) - 0.5;
    vec2 xf = floor(xy);
    vec2 f = xy - xf;
    ivec2 t = ivec2(xf);
    vec3 c00 = texelFetch(uEnvResidual, env_oct_tap(s, t), level).rgb;
    vec3 c10 = texelFetch(uEnvResidual, env_oct_tap(s, t + ivec2(1, 0)), level).rgb;
    vec3 c01 = texelFetch(uEnvResidual, env_oct_tap(s, t + ivec2(0, 1)), level).rgb;
    vec3 c11 = texelFetch(uEnvResidual, env_oct_tap(s, t + ivec2(1, 1)), level).rgb;
    return mix(mix(c00, c10, f.x), mix(c01, c11, f.x), f.y);
}

// The specular samples' radiance at direction w and level lod (already clamped to [0, uEnvMaxLod]):
// GL's trilinear textureLod of the lat-long chain, or the same filter by hand on the octahedral one;
// a Phong lobe's where the env lights are the GGX set's alone reads uEnv itself (lat-long).
vec3 env_lod(float alpha, vec3 w, float lod)
{
    if (uEnvLightsGGXOnly != 0 && !sl_lobe_is_ggx(alpha))
        return textureLod(uEnv, sl_dir_to_uv(w), lod).rgb;
    if (uEnvLayout == ENV_LAYOUT_OCT) {
        vec2 uv = env_oct_uv(w);
        int l0 = int(lod);
        float f = lod - float(l0);
        vec3 a = env_oct_bilinear(l0, uv);
        if (f == 0.0)
            return a;
        return mix(a, env_oct_bilinear(min(l0 + 1, int(uEnvMaxLod)), uv), f);
    }
    return textureLod(uEnvResidual, sl_dir_to_uv(w), lod).rgb;
}

// The G-buffer's lobe parameter (src/raster/gbuffer.h): >= 0 the Phong exponent, clamped to
// [0, MAX_ALPHA]; <= -1 GGX with r = -1 - alpha, clamped to r <= 1; (-1, 0), which no material
// writes, Phong 0.
float lobe_param(float a)
{
    return a <= -1.0 ? max(a, -2.0) : clamp(a, 0.0, MAX_ALPHA);
}

// Specular occlusion (src/occlusion/specular_occlusion.h, line for line): the share of the lobe's
// cone (about R, holding all but SO_LOBE_OUTSIDE of a Phong lobe's energy) inside the visibility
// cone (about the bent normal, cos = sqrt(1 - AO)), over the same share for the open hemisphere,
// fading to 1 as the AO nears 1.
const float SO_LOBE_OUTSIDE = 0.244;
const float SO_FADE = 0.8; // the factor fades to 1 over SO_FADE < AO < 1

float so_phong_exponent(float alpha)
{
    if (alpha >= 0.0)
        return alpha;
    float r = -1.0 - alpha;
    float a = max(r * r, 1e-4);
    return max(2.0 / (a * a) - 2.0, 0.0);
}

// acos as Abramowitz and Stegun 4.4.46's polynomial (|error| <= 2e-8 rad), the C side's
float so_acos(float x)
{
    float a = min(abs(x), 1.0);
    float p = -0.0012624911;
    p = p * a + 0.0066700901;
    p = p * a - 0.0170881256;
    p = p * a + 0.0308918810;
    p = p * a - 0.0501743046;
    p = p * a + 0.0889789874;
    p = p * a - 0.2145988016;
    p = p * a + 1.5707963050;
    float r = p * sqrt(1.0 - a);
    return x < 0.0 ? PI - r : r;
}

// the cosine of the lobe's cone (SO_LOBE_OUTSIDE of its energy outside), which depends on the
// lobe parameter alone; its angle is so_acos of it
float so_lobe_cos(float alpha)
{
    return pow(SO_LOBE_OUTSIDE, 1.0 / (so_phong_exponent(alpha) + 1.0));
}

// the lobe's cap: cosine cos_s, angle ts; the smaller cap over 2 pi is 1 - max(cos_v, cos_s)
float so_cap_share(float cos_v, float tv, float cos_s, float ts, float cos_d)
{
    float d = so_acos(cos_d);
    float lo = abs(tv - ts), hi = tv + ts;
    float inside = 1.0 - clamp((d - lo) / max(hi - lo, 1e-6), 0.0, 1.0);
    float cap = 1.0 - max(cos_v, cos_s);
    return clamp(cap * smoothstep(0.0, 1.0, inside) / max(1.0 - cos_s, 1e-12), 0.0, 1.0);
}

float specular_occlusion(float ao, float b_dot_r, float n_dot_v, float alpha)
{
    if (!(ao > 0.0))
        return 0.0;
    if (ao >= 1.0) // the fade's weight is 1: nothing hidden, exactly
        return 1.0;
    float cos_s = so_lobe_cos(alpha);
    float ts = so_acos(cos_s);
    float cos_v = sqrt(max(0.0, 1.0 - ao));
    float open = so_cap_share(0.0, 0.5 * PI, cos_s, ts, n_dot_v);
    float seen = so_cap_share(cos_v, so_acos(cos_v), cos_s, ts, b_dot_r);
    float so = open > 0.0 ? clamp(seen / open, 0.0, 1.0) : ao;
    return so + (1.0 - so) * smoothstep(SO_FADE, 1.0, ao);
}

// The diffuse term's lookup direction with the cone (src/shading/bent_irradiance.h): N bent
// towards the bent normal B by the share the occluders hide, 1 - AO; D = N on open ground.
vec3 bent_irradiance_dir(vec3 N, vec3 B, float ao)
{
    return normalize(N + (B - N) * (1.0 - ao));
}

// Unit normal, bent toward the eye where the interpolated normal faces away:
// N + (MIN_NDOTV - N.V) V has N.V = MIN_NDOTV before normalising. A zero normal becomes V.
vec3 facing_normal(vec3 N, vec3 V)
{
    float len2 = dot(N, N);
    if (!(len2 > TINY))
        return V;
    N = N * (1.0 / sqrt(len2));
    float NdotV = dot(N, V);
    if (NdotV < MIN_NDOTV)
        N = normalize(N + (MIN_NDOTV - NdotV) * V);
    return N;
}

// Reflection occlusion (src/occlusion/reflection.c, the pass whose plane the C port reads, step
// for step): the share of the lobe's rays that leave the scene, traced against the G-buffer. A
// texel traces one of five rays, (x + 2 y) mod 5: ray 0 along R, rays 1 .. 4 on a ring at
// REFLECTION_RING of the lobe's cone angle; a pixel averages the rays of its 3x3 block (itself
// and the neighbours on the same surface; a ray below its surface is not counted, one into the
// surface drawn, below the geometric normal's horizon, is blocked), each weighted by its cosine
// to the normal. Each ray takes REFLECTION_STEPS points t = D (k / steps)^2 and is blocked at the
// first behind a texel's tangent plane and within a thickness of it.
const int REFLECTION_RAYS = 5;
const int REFLECTION_BLOCK = 9;
const float REFLECTION_BELOW = -1.0; // a ray below the surface: no part of the visibility
const int REFLECTION_STEPS = 16;
const float REFLECTION_RING = 0.5;
const int REFLECTION_ELLIPSE = 1;   // the ring on the lobe's ellipse: twice the angle along, 2 N.V across
const float REFLECTION_PLANE_MIN = 1e-6; // R on N within this (squared sine): no plane of incidence
const float REFLECTION_THICKNESS = 0.1;
const float REFLECTION_OFFSET = 0.002;
const float REFLECTION_PLANE_EPS = 0.003;
const float REFLECTION_MIN_COSINE = 1e-6; // a ray's least weight (R at a silhouette)
const float REFLECTION_INTO_MARGIN = 0.15; // below the rebuilt normal's horizon by more: into it (none with the facet)
const float REFLECTION_SAME_DEPTH = 0.02;
const float REFLECTION_SAME_NORMAL = 0.998;
const int REFLECTION_LONE = 3; // a block counting fewer rays adds the pixel's own other rays

// The G-buffer texel q as a ray reads it: false when empty, else its position, its normal
// facing the eye and its view depth.
bool reflection_surface(ivec2 q, out vec3 Pq, out vec3 Nq, out float zq)
{
    Pq = vec3(0.0);
    Nq = vec3(0.0);
    zq = 0.0;
    if (texelFetch(uDepth, q, 0).r >= 1.0)
        return false;
    Pq = texelFetch(uPosition, q, 0).xyz;
    Nq = facing_normal(texelFetch(uNormal, q, 0).xyz, normalize(uEye - Pq));
    zq = dot(Pq - uEye, uViewForward);
    return true;
}

// 1 when the ray from P along the unit R leaves the image, the camera's front or its length
// unblocked, 0 at its first blocked point.
float reflection_trace_ray(vec3 P, vec3 R)
{
    vec3 d0 = P - uEye;
    float z0 = dot(d0, uViewForward), zr = dot(R, uViewForward);
    float x0 = dot(d0, uViewRight), xr = dot(R, uViewRight);
    float y0 = dot(d0, uViewUp), yr = dot(R, uViewUp);
    float prev_t = 0.0;
    for (int k = 1; k <= REFLECTION_STEPS; k++) {
        float s = float(k) / float(REFLECTION_STEPS);
        float t = uReflectionDistance * s * s;
        float z = z0 + zr * t;
        if (!(z > 1e-4))
            return 1.0; // behind the camera
        float scale_px = uPixelsPerUnit / z;
        float px = 0.5 * uViewport.x + (x0 + xr * t) * scale_px;
        float py = 0.5 * uViewport.y + (y0 + yr * t) * scale_px;
        if (!(px >= 0.0 && py >= 0.0 && px < uViewport.x && py < uViewport.y))
            return 1.0; // off the image
        vec3 Pc, Nc;
        float zc;
        bool covered = reflection_surface(ivec2(int(px), int(py)), Pc, Nc, zc);
        float thickness = max(t - prev_t, REFLECTION_THICKNESS * zc);
        prev_t = t;
        if (!covered || !(z > zc && z < zc + thickness)) // empty, in front of it or too far behind
            continue;
        float behind = dot(Nc, P + R * t) - dot(Nc, Pc);
        if (behind < -REFLECTION_PLANE_EPS * zc)
            return 0.0;
    }
    return 1.0;
}

// Along the image axis d from the covered texel q (position Pq, view depth zq): the step across
// it, between its two neighbours on the axis (a central difference) or between q and the one
// neighbour there is, counting a neighbour covered and within the thickness in view depth (farther,
// it is another surface); false where neither is.
bool reflection_axis_step(ivec2 q, ivec2 d, vec3 Pq, float zq, out vec3 step_across)
{
    vec3 ends[2] = vec3[](Pq, Pq);
    bool found = false;
    ivec2 size = ivec2(uViewport);
    for (int side = 0; side < 2; side++) {
        ivec2 n = q + (2 * side - 1) * d;
        if (n.x < 0 || n.y < 0 || n.x >= size.x || n.y >= size.y)
            continue;
        vec3 Pn, Nn;
        float zn;
        if (reflection_surface(n, Pn, Nn, zn) && abs(zn - zq) < REFLECTION_THICKNESS * zq) {
            ends[side] = Pn;
            found = true;
        }
    }
    step_across = ends[1] - ends[0];
    return found;
}

// The facet normal of texel q, decoded from uNormal.w and uKd.w (gbuffer.frag's facet_code);
// (0, 0, 0) for the code (2, 2): no plane.
vec3 facet_normal(ivec2 q)
{
    vec2 p = vec2(texelFetch(uNormal, q, 0).w, texelFetch(uKd, q, 0).w);
    if (abs(p.x) > 1.5)
        return vec3(0.0);
    vec3 n = vec3(p, 1.0 - abs(p.x) - abs(p.y));
    if (n.z < 0.0)
        n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return normalize(n);
}

// The covered texel q's geometric normal, facing V: the surface the rasterizer drew, which a
// smooth or normal-mapped N leans away from. The facet where the G-buffer has it (uHasFacet);
// else the normal of the plane its steps along x and y span, N where an axis has no step or the
// two span no plane.
vec3 reflection_geometric_normal(ivec2 q, vec3 Pq, float zq, vec3 V, vec3 N)
{
    if (uHasFacet != 0) {
        vec3 f = facet_normal(q);
        if (!(dot(f, f) > 0.0))
            return N;
        return dot(f, V) < 0.0 ? -f : f;
    }
    vec3 along_x, along_y;
    if (!reflection_axis_step(q, ivec2(1, 0), Pq, zq, along_x) ||
        !reflection_axis_step(q, ivec2(0, 1), Pq, zq, along_y))
        return N;
    vec3 n = cross(along_x, along_y);
    float len = length(n);
    if (!(len > 0.0))
        return N;
    n /= len;
    return dot(n, V) < 0.0 ? -n : n;
}

// Ring ray direction: R turned at the phase in the lobe's frame, T in the plane of incidence from
// R towards N, B = R x T across it, on the lobe's ellipse about R: twice the ring's angle in the
// plane, 2 N.V times it across, as a microfacet lobe's reflection is (reflection.c
// ring_direction). At N.V = 1 (no plane of incidence) the helper axis's frame.
vec3 reflection_ring_direction(vec3 N, vec3 R, float n_dot_v, float phase, float ring)
{
    vec3 toward_n = N - R * n_dot_v;
    float len2 = dot(toward_n, toward_n);
    vec3 helper = abs(R.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    vec3 T = len2 > REFLECTION_PLANE_MIN ? toward_n * (1.0 / sqrt(len2)) : normalize(cross(R, helper));
    vec3 B = cross(R, T);
    float along = REFLECTION_ELLIPSE != 0 ? 2.0 : 1.0;
    float across = REFLECTION_ELLIPSE != 0 ? 2.0 * max(n_dot_v, 0.0) : 1.0;
    vec3 side = T * (along * cos(phase)) + B * (across * sin(phase));
    return normalize(R * cos(ring) + side * sin(ring));
}

// Ray k of the covered texel q: 1 open, 0 blocked, REFLECTION_BELOW below its surface; its weight
// in the block's share, its cosine to the normal (at least REFLECTION_MIN_COSINE). A ray above
// N's horizon and below the geometric normal's (by more than REFLECTION_INTO_MARGIN with the
// rebuilt normal) enters the surface drawn: with the facet not counted (the lighting leaves the
// directions under the facet out: facet_hides), with the rebuilt normal blocked; not traced.
float reflection_ray(ivec2 q, int k, out float weight)
{
    vec3 Pq = texelFetch(uPosition, q, 0).xyz;
    vec3 V = normalize(uEye - Pq);
    vec3 N = facing_normal(texelFetch(uNormal, q, 0).xyz, V);
    float n_dot_v = dot(N, V);
    vec3 R = N * (2.0 * n_dot_v) - V;
    float depth = dot(Pq - uEye, uViewForward);
    vec3 Ng = reflection_geometric_normal(q, Pq, depth, V, N);
    float margin = uHasFacet != 0 ? 0.0 : REFLECTION_INTO_MARGIN;
    float under = uHasFacet != 0 ? REFLECTION_BELOW : 0.0; // a ray into the surface drawn
    vec3 P = Pq + N * (REFLECTION_OFFSET * depth);
    if (k == 0) {
        weight = max(dot(R, N), REFLECTION_MIN_COSINE);
        return dot(R, Ng) < -margin ? under : reflection_trace_ray(P, R);
    }
    float alpha = lobe_param(texelFetch(uKsAlpha, q, 0).a);
    float ring = REFLECTION_RING * so_acos(so_lobe_cos(alpha));
    float phase = 2.0 * PI * float(k - 1) / float(REFLECTION_RAYS - 1);
    vec3 Rk = reflection_ring_direction(N, R, n_dot_v, phase, ring);
    float cosine = dot(Rk, N);
    weight = max(cosine, REFLECTION_MIN_COSINE);
    if (!(cosine > 0.0))
        return REFLECTION_BELOW; // not counted
    return dot(Rk, Ng) < -margin ? under : reflection_trace_ray(P, Rk);
}

// The covered pixel's visibility: the share of open rays over its block (the pixel, x + 1,
// x - 1, y + 1, y - 1, then the corners), each weighted by its cosine, a neighbour counted where
// it is the same surface (near the pixel's tangent plane, its normal within a few degrees: its ray
// then stands for the pixel's), and the pixel's own other rays where the block counts fewer than
// REFLECTION_LONE; and in y how many rays it is over.
vec2 reflection_visibility(ivec2 pixel)
{
    const ivec2 offsets[REFLECTION_BLOCK] = ivec2[](ivec2(0, 0), ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1),
                                                    ivec2(0, -1), ivec2(1, 1), ivec2(-1, 1), ivec2(1, -1),
                                                    ivec2(-1, -1));
    vec3 Pp, Np;
    float zp;
    reflection_surface(pixel, Pp, Np, zp);
    float dp = dot(Np, Pp);
    ivec2 size = ivec2(uViewport);
    float open = 0.0, total = 0.0; // the counted rays' weights: the open ones', all
    int count = 0;
    for (int m = 0; m < REFLECTION_BLOCK; m++) {
        ivec2 q = pixel + offsets[m];
        if (q.x < 0 || q.y < 0 || q.x >= size.x || q.y >= size.y)
            continue;
        if (m > 0) {
            vec3 Pq, Nq;
            float zq;
            if (!reflection_surface(q, Pq, Nq, zq))
                continue;
            float off = dot(Np, Pq) - dp;
            if (!(abs(off) < REFLECTION_SAME_DEPTH * zp && dot(Np, Nq) > REFLECTION_SAME_NORMAL))
                continue;
        }
        float weight;
        float ray = reflection_ray(q, (q.x + 2 * q.y) % REFLECTION_RAYS, weight);
        if (ray < 0.0)
            continue; // below its surface
        open += ray * weight;
        total += weight;
        count++;
    }
    if (count < REFLECTION_LONE) { // an edge, a normal map's bumps: the pixel's own other rays too
        int own = (pixel.x + 2 * pixel.y) % REFLECTION_RAYS;
        for (int k = 0; k < REFLECTION_RAYS; k++) {
            if (k == own)
                continue;
            float weight;
            float ray = reflection_ray(pixel, k, weight);
            if (ray < 0.0)
                continue; // below its surface
            open += ray * weight;
            total += weight;
            count++;
        }
    }
    return count > 0 ? vec2(open / total, float(count)) : vec2(1.0, 0.0);
}

// The specular's factor with the cone's (`capped`) and the rays' (`reflection`: visibility,
// rays): the smaller of the two with one ray, the material's occlusion times the rays'
// visibility with five or more, mixed between by the rays' count.
float reflection_specular_factor(float capped, float material, vec2 reflection)
{
    float weight = clamp((reflection.y - 1.0) * (1.0 / float(REFLECTION_RAYS - 1)), 0.0, 1.0);
    float both = min(capped, reflection.x), alone = material * reflection.x;
    return both + (alone - both) * weight;
}

// The pole-free irradiance maps (ported in src/ibl/irradiance_map.c): vertex-centred grids,
// grid point p in [-1, 1] at texel centre (p / 2 + 1/2) (S - 1) / S + 1 / (2 S), clamped to the
// outer texel centres.
float irradiance_grid_coord(float p, float s)
{
    float t = (p * 0.5 + 0.5) * ((s - 1.0) / s) + 0.5 / s;
    t = t > 0.5 / s ? t : 0.5 / s;
    return t < 1.0 - 0.5 / s ? t : 1.0 - 0.5 / s;
}

// Octahedral: p = N.xy / |N|_1, folded below the equator (sl_irradiance_oct_uv).
vec2 irradiance_oct_uv(vec3 n, float s)
{
    float a = abs(n.x) + abs(n.y) + abs(n.z);
    float px = n.x / a, py = n.y / a;
    if (n.z < 0.0) {
        float fx = (1.0 - abs(py)) * (px >= 0.0 ? 1.0 : -1.0);
        float fy = (1.0 - abs(px)) * (py >= 0.0 ? 1.0 : -1.0);
        px = fx;
        py = fy;
    }
    return vec2(irradiance_grid_coord(px, s), irradiance_grid_coord(py, s));
}

// Dual paraboloid: z >= 0 in the left half at N.xy / (1 + z), z < 0 in the right half at
// N.xy / (1 - z) (sl_irradiance_dp_uv).
vec2 irradiance_dp_uv(vec3 n, float s)
{
    float half_ = n.z >= 0.0 ? 0.0 : 1.0;
    float d = 1.0 + abs(n.z);
    float px = n.x / d, py = n.y / d;
    return vec2((irradiance_grid_coord(px, s) + half_) * 0.5, irradiance_grid_coord(py, s));
}

// Irradiance E(N) of the (unscaled) environment, N in environment space (ported in
// src/ibl/irradiance.c, sl_irradiance_eval): SH9 or one fetch from a map, clamped at 0 (SH9
// rings below 0 opposite a strong sun).
vec3 irradiance(vec3 N)
{
    vec3 e;
    if (uIrradianceMethod == IRRADIANCE_SH9) {
        const float k0 = 0.282094792, k1 = 0.488602512, k2 = 1.092548431, k3 = 0.315391565,
                    k4 = 0.546274215;
        float x = N.x, y = N.y, z = N.z;
        e = uSH[0] * k0;
        e = e + uSH[1] * (k1 * y);
        e = e + uSH[2] * (k1 * z);
        e = e + uSH[3] * (k1 * x);
        e = e + uSH[4] * (k2 * x * y);
        e = e + uSH[5] * (k2 * y * z);
        e = e + uSH[6] * (k3 * (3.0 * z * z - 1.0));
        e = e + uSH[7] * (k2 * x * z);
        e = e + uSH[8] * (k4 * (x * x - y * y));
    } else if (uIrradianceMethod == IRRADIANCE_OCT) {
        float s = float(textureSize(uIrradianceMap, 0).y);
        e = textureLod(uIrradianceMap, irradiance_oct_uv(N, s), 0.0).rgb;
    } else if (uIrradianceMethod == IRRADIANCE_DP) {
        float s = float(textureSize(uIrradianceMap, 0).y);
        e = textureLod(uIrradianceMap, irradiance_dp_uv(N, s), 0.0).rgb;
    } else {
        e = textureLod(uIrradianceMap, sl_dir_to_uv(N), 0.0).rgb;
    }
    return max(e, vec3(0.0));
}

// The specular's part from across the horizon, with the sky maps (src/shading/lighting_internal.h
// shade_horizon says why): the samples whose w lies on the other side of the horizon (z >= 0 is
// the sky's) from R are summed apart, with their directions weighted by |luminance|; main adds
// the part times its map's visibility (horizon_visible) after the specular's occlusion.
bool gHorizonOn;  // the maps are drawn: split
bool gHorizonSky; // R on the sky's side
vec3 gHorizonSum; // the contributions from across, over the estimate's count
vec3 gHorizonDir; // their directions times |luminance|
vec3 gFacet;      // the pixel's facet normal, environment space (facet_env), 0: none

// whether the specular is split at the horizon: the maps are drawn
bool horizon_on()
{
    return SL_SKY_MAPS != 0 && uSkyMapCount > 0;
}

void horizon_for(vec3 N, vec3 V, vec3 F)
{
    vec3 R = N * (2.0 * dot(N, V)) - V;
    gHorizonOn = horizon_on();
    gHorizonSky = R.z >= 0.0;
    gFacet = F;
    gHorizonSum = vec3(0.0);
    gHorizonDir = vec3(0.0);
}

// Whether direction w (environment space) lies under the pixel's facet, the drawn triangle's
// plane, which a smooth or normal-mapped N leans across at a rim: the surface itself hides it,
// and every estimator leaves it out as one below N's horizon (src/shading/lighting_internal.h
// shade_facet_hides). A zero facet hides nothing.
bool facet_hides(vec3 w)
{
    return dot(w, gFacet) < 0.0;
}

// The pixel's facet normal in environment space: with reflection occlusion on and the facet in
// the G-buffer (uHasFacet), else 0 (lighting_internal.h shade_facet_env)
vec3 facet_env(ivec2 pixel)
{
    if (!(uReflectionDistance > 0.0) || uHasFacet == 0)
        return vec3(0.0);
    return uEnvRotation * facet_normal(pixel);
}

bool horizon_across(vec3 w)
{
    return gHorizonOn && (w.z >= 0.0) != gHorizonSky;
}

void horizon_add(vec3 w, vec3 c)
{
    gHorizonSum = gHorizonSum + c;
    gHorizonDir = gHorizonDir + w * abs(dot(c, vec3(0.2126, 0.7152, 0.0722)));
}

// A sun's glow (src/shading/lighting_internal.h shade_glow says why): with the env lights' maps,
// a sample whose w lies in a map's glow is times that map's visibility before it is summed.
int gGlowCount;                     // the maps whose glow applies (0: none)
float gGlowVis[SHADOW_SUN_MAX];     // each map's visibility from the pixel's point (env_light_visibility)

void glow_for(bool envShadow)
{
    gGlowCount = envShadow ? uEnvGlowCount : 0;
}

// c times the visibility of the map whose direction is nearest w, where w lies in its glow
vec3 glow(vec3 w, vec3 c)
{
    float nearest = -2.0;
    int map = -1;
    for (int k = 0; k < gGlowCount; k++) {
        float d = dot(w, uEnvGlow[k].xyz);
        if (d > nearest) {
            nearest = d;
            map = k;
        }
    }
    return map >= 0 && nearest >= uEnvGlow[map].w ? c * gGlowVis[map] : c;
}

// Specular IBL, eq. (3): N, V unit in environment space, N.V >= MIN_NDOTV.
vec3 specular_ibl(vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation)
{
    float NdotV = dot(N, V);
    vec3 R = normalize(2.0 * NdotV * N - V);
    vec3 axis = (R.x * R.x + R.y * R.y < POLE_EPS) ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 0.0, 1.0);
    vec3 A = normalize(cross(axis, R));
    vec3 B = normalize(cross(R, A));
    int n = int(uHammersley.N);
    vec3 sum = vec3(0.0);
    for (int k = 0; k < n; k++) {
        vec2 xi = hammersley_point(k);
        if (uRotate != 0)
            xi = vec2(fract(xi.x + rotation.x), fract(xi.y + rotation.y));
        vec3 L = skewed_sample(xi, alpha);
        float pdf = sample_pdf(xi, alpha);
        vec3 w = normalize(L.x * A + L.y * B + L.z * R);
        float wN = dot(w, N);
        if (wN <= 0.0 || facet_hides(w))
            continue;
        vec3 H = normalize(w + V);
        float NdotH = dot(N, H);
        float LdotH = dot(w, H);
        float D = sl_lobe_D(NdotH, alpha);
        vec3 F = sl_brdf_F(Ks, LdotH);
        float G = sl_lobe_G(LdotH, wN, NdotV, alpha, uGTerm);
        float lod = mip_level(alpha, D, pdf, w);
        vec3 Li = env_lod(alpha, w, lod) * uEnvIntensity;
        float weight = G * wN / 4.0;
        if (estimator_of(alpha) == ESTIMATOR_CONSISTENT)
            weight = weight * D / pdf;
        vec3 c = glow(w, F * Li * weight);
        if (horizon_across(w))
            horizon_add(w, c);
        else
            sum = sum + c;
    }
    gHorizonSum = gHorizonSum * (1.0 / float(max(n, 1)));
    return sum * (1.0 / float(max(n, 1)));
}

// Microfacet sampling, step 1: H about +Z with density D(H) (N.H). D is normalised so that
// (alpha + 2) int_0^1 c^(alpha+1) dc = 1 (c = N.H), so c has the CDF c^(alpha+2) and
// c = xi2^(1/(alpha+2)); the azimuth is eq. (4)'s, as in skewed_sample (only the exponent differs).
// GGX (alpha < 0): c = ggx_cos_theta, which is GGX's D(H) (N.H) exactly.
vec3 microfacet_sample(vec2 xi, float alpha)
{
    float c = sl_lobe_is_ggx(alpha) ? ggx_cos_theta(xi.y, sl_ggx_a2(alpha)) : pow(xi.y, 1.0 / (alpha + 2.0));
    vec2 uv = vec2(xi.x, acos(clamp(c, -1.0, 1.0)) / PI);
    return sl_uv_to_dir(uv);
}

// D(H) of the drawn H: (N.H)^alpha = xi2^(alpha/(alpha+2)) exactly (N.H = xi2^(1/(alpha+2))); the
// xi form does not underflow at large alpha as pow(N.H, alpha) does. GGX: ggx_D_of_xi.
float microfacet_D(vec2 xi, float alpha)
{
    if (sl_lobe_is_ggx(alpha))
        return ggx_D_of_xi(xi.y, sl_ggx_a2(alpha));
    return (alpha + 2.0) / (2.0 * PI) * pow(xi.y, alpha / (alpha + 2.0));
}

// GGX's microfacet sampling draws H from the visible normals (Heitz 2018), by Dupuy and
// Benyoub's spherical caps (2023): with V stretched to the unit-roughness configuration,
// Vh = normalize(a V.x, a V.y, V.z) in the frame about N (ggx_stretched_view, once a pixel), a
// point c on the unit sphere's cap z > -Vh.z (z uniform, the azimuth eq. (4)'s of xi.x),
// H = normalize(a h.x, a h.y, h.z) for h = c + Vh. H has the density
// D_V(H) = G1(V) max(V.H, 0) D(H) / (N.V), so w = reflect(-V, H) has
// p(w) = G1(V) D(H) / (4 N.V) = D(H) / ggx_visible_norm, and the estimator's weight
// f (w.N) / p(w) is F G2 / G1(V) <= F. Drawn from D(H) (N.H) instead, a grazing view wastes the
// draws whose facet faces away (V.H <= 0) and overweights the rest by up to 2 / (N.V).
vec3 ggx_visible_normal(vec2 xi, vec3 Vh, float a)
{
    float phi = 2.0 * PI * (0.5 - xi.x);
    float z = (1.0 - xi.y) * (1.0 + Vh.z) - Vh.z;
    float st = sqrt(clamp(1.0 - z * z, 0.0, 1.0));
    vec3 h = vec3(st * cos(phi), st * sin(phi), z) + Vh;
    vec3 H = vec3(a * h.x, a * h.y, h.z);
    return H / max(length(H), TINY); // h = 0 (c = -Vh, a point of measure 0): H = 0, dropped as V.H <= 0
}

// V in the frame about N (Vl) stretched by a = sqrt(a^2) to the unit-roughness configuration.
vec3 ggx_stretched_view(vec3 Vl, float a)
{
    return normalize(vec3(a * Vl.x, a * Vl.y, Vl.z));
}

// 4 (N.V) / G1(V) = 2 (N.V + sqrt((N.V)^2 (1 - a^2) + a^2)): the visible normals' p(w) is D(H) over it.
float ggx_visible_norm(float NdotV, float a2)
{
    return 2.0 * (NdotV + sqrt(NdotV * NdotV * (1.0 - a2) + a2));
}

// The control variate's kernel for one pixel (specular_cv; C: sl_cv_kernel): each sample's
// radiance is subtracted times scale K(w) / p(w), K = ca k_a + cb k_b about dir.
struct CvKernel {
    bool on;    // false: the microfacet estimator, nothing subtracted
    vec3 dir;   // the lookup direction, the kernels' axis
    int set;    // the chain's set
    int la, lb; // the levels read
    float ca, cb; // their exact shares
    vec3 scale; // beta E
};

CvKernel no_cv()
{
    return CvKernel(false, vec3(0.0), 0, 0, 0, 0.0, 0.0, vec3(0.0));
}

// The levels a chain read at lod mixes, la with 1 - f and lb = la + 1 with f, and those weights
// where the level is exact (from uSplitSumExactLevel on), 0 where it is not (level 0, the
// environment itself, and the sampled levels): cv.ca, cv.cb (src/shading/splitsum_lut.h).
void cv_levels(float lod, inout CvKernel cv)
{
    int max_lod = int(uSplitSumMaxLod);
    lod = clamp(lod, 0.0, float(max_lod));
    cv.la = min(int(lod), max_lod);
    cv.lb = cv.la < max_lod ? cv.la + 1 : max_lod;
    float f = cv.lb > cv.la ? lod - float(cv.la) : 0.0;
    cv.ca = cv.la >= uSplitSumExactLevel ? 1.0 - f : 0.0;
    cv.cb = cv.lb > cv.la && cv.lb >= uSplitSumExactLevel ? f : 0.0;
}

// Level k's kernel of set `set` at c = w.d (src/ibl/ibl.h sl_prefilter_kernel): the density
// D(h) G'(c) c / (4 Z) of w about the lookup direction d at N = V = d, h the half vector of w and
// d, (d.h)^2 = (1 + c) / 2; 0 for c <= 0.
float cv_kernel_level(int set, int level, float c)
{
    if (!(c > 0.0))
        return 0.0;
    float r = float(level) / uSplitSumMaxLod;
    float a = max(r * r, GGX_MIN_A);
    float a2 = a * a;
    float nh2 = 0.5 * (1.0 + c);
    float D;
    float G;
    if (set == SPLITSUM_GGX) {
        float t = (1.0 - nh2) + nh2 * a2;
        D = a2 / (PI * t * t);
        G = 2.0 / (c + sqrt(c * c * (1.0 - a2) + a2));
    } else {
        float alpha = min(2.0 / a2 - 2.0, MAX_ALPHA);
        D = (alpha + 2.0) / (2.0 * PI) * pow(nh2, 0.5 * alpha);
        G = set == SPLITSUM_PHONG_ONE ? 1.0 : 1.0 / max(nh2, 1e-6);
    }
    return 0.25 * D * G * c * uSplitSumKernelNorm[set * SPLITSUM_LEVELS + level];
}

// The kernel mix K = ca k_a + cb k_b the exact part of the chain read stands for.
float cv_kernel(CvKernel cv, float c)
{
    float K = 0.0;
    if (cv.ca > 0.0)
        K += cv.ca * cv_kernel_level(cv.set, cv.la, c);
    if (cv.cb > 0.0)
        K += cv.cb * cv_kernel_level(cv.set, cv.lb, c);
    return K;
}

// Specular IBL by microfacet importance sampling (uEstimator == 3): eq. (1) with the specular
// term of eq. (2), f = D G F / (4 (w.N)(V.N)), by Monte Carlo with directions drawn through H:
//   H ~ p_H(H) = D(H) (N.H) about N (microfacet_sample, in the tangent frame A, B, N);
//   w = reflect(-V, H) = 2 (V.H) H - V, hence L.H = w.H = V.H; the map H -> w has
//   dw/dH = 4 (V.H), so the density of w is p(w) = D(H) (N.H) / (4 (V.H));
//   term = f L(w) (w.N) / p(w)
//        = [D G F / (4 (w.N)(V.N))] L (w.N) [4 (V.H) / (D (N.H))]
//        = F(V.H) L(w) G' (w.N) (V.H) / (N.H),    G' = G / ((w.N)(V.N)) = 1/(V.H)^2 or 1.
// D cancels. Every w with w.N > 0 has p(w) > 0 (H = normalize(w + V) has N.H > 0), so the
// estimator converges to eq. (1) (up to the mip filter's blur); and w.N > 0 needs
// 2 (V.H)(N.H) > V.N, so N.H > V.N / (2 V.H) and the weight G' (w.N)(V.H)/(N.H) is at most
// 2 / (V.N) for both G choices: bounded (200 at the bent-normal floor N.V = 0.01), where the
// consistent estimator's D/p is not. Samples with V.H <= 0 (the microfacet faces away from
// the eye) or w.N <= 0 (reflected below the horizon) contribute 0 (docs/conventions.md,
// erratum 2). GGX draws H from the visible normals instead (ggx_visible_normal): p(w) =
// D(H) / norm, norm = ggx_visible_norm, and the term F L G' (w.N) norm / 4 = F L G2 / G1(V),
// G' = 4 Vis; every draw has V.H > 0 and a weight at most 1. N.H is the drawn
// cos(theta_h), H's z in the frame. The mip level takes D(H) for the spec rules, as written,
// and p(w) for gems (docs/lighting.md "Estimators").
// cv: the control variate's kernel, whose K(w) / p(w) cv.scale Li every sample subtracts when
// cv.on (specular_cv).
vec3 specular_microfacet(vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation, CvKernel cv)
{
    float NdotV = dot(N, V);
    vec3 axis = (N.x * N.x + N.y * N.y < POLE_EPS) ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 0.0, 1.0);
    vec3 A = normalize(cross(axis, N));
    vec3 B = normalize(cross(N, A));
    // GGX: the stretched view and the visible normals' norm, once a pixel (a Phong lobe reads neither)
    bool ggx = sl_lobe_is_ggx(alpha);
    float a2 = ggx ? sl_ggx_a2(alpha) : 0.0, a = sqrt(a2);
    vec3 Vh = ggx ? ggx_stretched_view(vec3(dot(V, A), dot(V, B), NdotV), a) : vec3(0.0);
    float norm = ggx ? ggx_visible_norm(NdotV, a2) : 1.0;
    int n = int(uHammersley.N);
    vec3 sum = vec3(0.0);
    for (int k = 0; k < n; k++) {
        vec2 xi = hammersley_point(k);
        if (uRotate != 0)
            xi = vec2(fract(xi.x + rotation.x), fract(xi.y + rotation.y));
        vec3 Hl = ggx ? ggx_visible_normal(xi, Vh, a) : microfacet_sample(xi, alpha);
        float D = ggx ? sl_ggx_D(Hl.z, a2) : microfacet_D(xi, alpha);
        vec3 H = normalize(Hl.x * A + Hl.y * B + Hl.z * N);
        float VdotH = dot(V, H);
        vec3 w = normalize(2.0 * VdotH * H - V);
        float wN = dot(w, N);
        bool lit = wN > 0.0 && !facet_hides(w);
        if (VdotH <= 0.0 || (!lit && !cv.on))
            continue;
        float NdotH = Hl.z;
        float pdf = ggx ? D / norm : D * NdotH / (4.0 * VdotH);
        vec3 F = sl_brdf_F(Ks, VdotH);
        float G = sl_lobe_G(VdotH, wN, NdotV, alpha, uGTerm);
        float lod = mip_level(alpha, D, pdf, w);
        vec3 Li = env_lod(alpha, w, lod) * uEnvIntensity;
        float weight = ggx ? G * wN * norm / 4.0 : G * wN * VdotH / NdotH;
        vec3 c = lit ? F * Li * weight : vec3(0.0);
        if (cv.on) // below the horizon too: the kernel reaches there, the BRDF does not
            c = c - cv.scale * Li * (cv_kernel(cv, dot(w, cv.dir)) / pdf);
        c = glow(w, c);
        if (horizon_across(w))
            horizon_add(w, c);
        else
            sum = sum + c;
    }
    gHorizonSum = gHorizonSum * (1.0 / float(max(n, 1)));
    return sum * (1.0 / float(max(n, 1)));
}

// MIS, the environment's side (src/ibl/env_dist.h): the level-0 texel of uEnvResidual that holds
// direction w, where the MIS estimator reads radiance (no filter: the truth's piecewise-constant map).
ivec2 env_texel(vec3 w)
{
    vec2 uv = sl_dir_to_uv(w);
    ivec2 size = textureSize(uEnvResidual, 0);
    return ivec2(min(int(uv.x * float(size.x)), size.x - 1), min(int(uv.y * float(size.y)), size.y - 1));
}

// The environment distribution's density (per sr) at the directions of level-0 texel t.
float env_dist_pdf(ivec2 t)
{
    return texelFetch(uEnvDist, ivec2(t.x >> uEnvDistShift, t.y >> uEnvDistShift), 0).g;
}

// A direction drawn from the environment distribution by inversion: the row j whose marginal CDF
// first exceeds xi.y, the column i whose conditional CDF first exceeds xi.x (binary searches),
// then uniform in solid angle inside texel (i, j): cos(theta) linear in the row's remainder t,
// phi linear in the column's s. Returns (w, density); `texel` is the level-0 texel inside (i, j)
// that holds w, clamped to it so that the radiance read is the drawn texel's.
vec4 env_dist_sample(vec2 xi, out ivec2 texel)
{
    ivec2 size = textureSize(uEnvDist, 0);
    int lo = 0;
    int hi = size.y - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (texelFetch(uEnvDistMarginal, ivec2(mid, 0), 0).r > xi.y)
            hi = mid;
        else
            lo = mid + 1;
    }
    int j = lo;
    float m0 = j > 0 ? texelFetch(uEnvDistMarginal, ivec2(j - 1, 0), 0).r : 0.0;
    float m1 = texelFetch(uEnvDistMarginal, ivec2(j, 0), 0).r;
    float t = (xi.y - m0) / (m1 - m0);
    lo = 0;
    hi = size.x - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (texelFetch(uEnvDist, ivec2(mid, j), 0).r > xi.x)
            hi = mid;
        else
            lo = mid + 1;
    }
    int i = lo;
    float c0 = i > 0 ? texelFetch(uEnvDist, ivec2(i - 1, j), 0).r : 0.0;
    float c1 = texelFetch(uEnvDist, ivec2(i, j), 0).r;
    float s = (xi.x - c0) / (c1 - c0);
    float z0 = cos(PI * float(j) / float(size.y));
    float z1 = cos(PI * float(j + 1) / float(size.y));
    float z = z0 + (z1 - z0) * t;
    float u = (float(i) + s) / float(size.x);
    float phi = 2.0 * PI * (0.5 - u);
    float st = sqrt(max(1.0 - z * z, 0.0));
    vec3 w = vec3(cos(phi) * st, sin(phi) * st, z);
    int f = 1 << uEnvDistShift;
    ivec2 size0 = textureSize(uEnvResidual, 0);
    int i0 = int(u * float(size0.x));
    int j0 = int(acos(clamp(z, -1.0, 1.0)) / PI * float(size0.y));
    texel = ivec2(clamp(i0, i * f, i * f + f - 1), clamp(j0, j * f, j * f + f - 1));
    return vec4(w, texelFetch(uEnvDist, ivec2(i, j), 0).g);
}

// The power heuristic's weight of a sample drawn with density p against the other strategy's q
// (both with N samples): p^2 / (p^2 + q^2), as 1 / (1 + (q/p)^2) so that neither square overflows.
float mis_power(float p, float q)
{
    float r = q / max(p, TINY);
    return 1.0 / (1.0 + r * r);
}

// Specular IBL by multiple importance sampling (uEstimator == 5): per Hammersley pair (the block
// holds (N + 1) / 2 of them for the user's N samples: N samples in all, as the others), one
// direction drawn as specular_microfacet draws it (density p_b(w) = D (N.H) / (4 V.H)) and one
// from the environment (env_dist_sample, density p_e(w)); each adds f L (w.N) / p times its
// power-heuristic weight p^2 / (p_b^2 + p_e^2), and the sum is divided by the pair count n:
//   BRDF sample: F L G' (w.N)(V.H)/(N.H) mis_power(p_b, p_e)   (specular_microfacet's term)
//   env sample:  F L D G' (w.N) / (4 p_e) mis_power(p_e, p_b)  (the BRDF (2) at w over p_e)
// The weights of a direction sum to 1 over the two strategies, and the BRDF's draws reach every w
// above the horizon, so the estimator converges to eq. (1) over the piecewise-constant map it reads
// (level 0, no filter: the ground truth's integrand), with no mip level at all. A sun of a few
// texels is drawn by the environment's samples at its own density (weight near 1 there), a sharp
// lobe by the BRDF's. Contributes 0 where the BRDF does: w.N <= 0, V.H <= 0. The environment's
// draws shift xi.x (the radical inverse, which is 0 for pair 0) by half a stratum, 1/(2N) mod 1,
// as xi.y = (k + 1/2)/N already is: unshifted, pair 0 always reads the first column of its row
// (a dim texel beside a sun, drawn at its tiny density and then weighed away by the BRDF's
// density): one wasted sample of N, -3% at N = 32 on a sun.
// With cv.on (specular_cv for cvmis) every sample also subtracts cv.scale K(w) Li / p times its weight,
// below the horizon too, where K reaches and the BRDF does not; an environment sample the BRDF's
// draws cannot reach (N.H <= 0 or w.H <= 0) has p_b = 0 and the weight 1.
vec3 specular_mis(vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation, CvKernel cv)
{
    float NdotV = dot(N, V);
    vec3 axis = (N.x * N.x + N.y * N.y < POLE_EPS) ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 0.0, 1.0);
    vec3 A = normalize(cross(axis, N));
    vec3 B = normalize(cross(N, A));
    int n = int(uHammersley.N);
    float half_ = 0.5 / float(max(n, 1));
    vec3 sum = vec3(0.0);
    for (int k = 0; k < n; k++) {
        vec2 xi = hammersley_point(k);
        if (uRotate != 0)
            xi = vec2(fract(xi.x + rotation.x), fract(xi.y + rotation.y));
        vec3 Hl = microfacet_sample(xi, alpha);
        float D = microfacet_D(xi, alpha);
        vec3 H = normalize(Hl.x * A + Hl.y * B + Hl.z * N);
        float VdotH = dot(V, H);
        vec3 w = normalize(2.0 * VdotH * H - V);
        float wN = dot(w, N);
        bool lit = wN > 0.0 && !facet_hides(w);
        if (VdotH > 0.0 && (lit || cv.on)) {
            float NdotH = Hl.z;
            float pdf = D * NdotH / (4.0 * VdotH);
            ivec2 t = env_texel(w);
            float pe = env_dist_pdf(t);
            float mis = mis_power(pdf, pe);
            vec3 F = sl_brdf_F(Ks, VdotH);
            float G = sl_lobe_G(VdotH, wN, NdotV, alpha, uGTerm);
            vec3 Li = texelFetch(uEnvResidual, t, 0).rgb * uEnvIntensity;
            float weight = lit ? G * wN * VdotH / NdotH * mis : 0.0;
            vec3 c = F * Li * weight;
            if (cv.on)
                c = c - cv.scale * Li * (cv_kernel(cv, dot(w, cv.dir)) / pdf * mis);
            c = glow(w, c);
            if (horizon_across(w))
                horizon_add(w, c);
            else
                sum = sum + c;
        }
        ivec2 te;
        vec2 xe = vec2(fract(xi.x + half_), xi.y);
        vec4 e = env_dist_sample(xe, te);
        vec3 we = e.xyz;
        float weN = dot(we, N);
        vec3 He = normalize(we + V);
        float NdotHe = dot(N, He);
        float LdotHe = dot(we, He);
        bool lit_e = weN > 0.0 && NdotHe > 0.0 && LdotHe > 0.0 && !facet_hides(we);
        if (lit_e || cv.on) {
            bool reached = NdotHe > 0.0 && LdotHe > 0.0;
            float De = reached ? sl_lobe_D(NdotHe, alpha) : 0.0;
            float pb = reached ? De * NdotHe / (4.0 * LdotHe) : 0.0;
            float mis = mis_power(e.w, pb);
            vec3 F = sl_brdf_F(Ks, LdotHe);
            float G = lit_e ? sl_lobe_G(LdotHe, weN, NdotV, alpha, uGTerm) : 0.0;
            vec3 Li = texelFetch(uEnvResidual, te, 0).rgb * uEnvIntensity;
            float weight = lit_e ? De * G * weN / (4.0 * e.w) * mis : 0.0;
            vec3 c = F * Li * weight;
            if (cv.on)
                c = c - cv.scale * Li * (cv_kernel(cv, dot(we, cv.dir)) / e.w * mis);
            c = glow(we, c);
            if (horizon_across(we))
                horizon_add(we, c);
            else
                sum = sum + c;
        }
    }
    gHorizonSum = gHorizonSum * (1.0 / float(max(n, 1)));
    return sum * (1.0 / float(max(n, 1)));
}

// The lobe width of the split-sum chain and table: GGX's roughness, or the Phong exponent's
// equal-peak one (2 / (alpha + 2))^(1/4) (src/shading/splitsum_lut.h)
float splitsum_width(float alpha)
{
    return sl_lobe_is_ggx(alpha) ? -1.0 - alpha : sqrt(sqrt(2.0 / (alpha + 2.0)));
}

// The table at the texel centres of its set: N.V = i / (S - 1) is column i, r = j / (S - 1) row
// set S + j. A, B, the direction factor t and the control variate's beta.
vec4 splitsum_lut(int set, float NdotV, float r)
{
    float s = float(SPLITSUM_LUT_SIZE);
    vec2 uv = vec2((clamp(NdotV, 0.0, 1.0) * (s - 1.0) + 0.5) / s,
                   (float(set) * s + clamp(r, 0.0, 1.0) * (s - 1.0) + 0.5) / (s * float(SPLITSUM_SETS)));
    return texture(uSplitSumLut, uv);
}

// The lookup direction: the lobe's centroid, which leans from R towards N away from normal view
// (t from the table, src/shading/splitsum_lut.h)
vec3 splitsum_dir(vec3 N, vec3 R, float t)
{
    return normalize(N * (1.0 - t) + R * t);
}

// The split sum's prefiltered radiance (before the intensity): the chain of the lobe's set along
// the lobe's centroid at the lobe's level; the table's A, B, t in ab.
vec3 splitsum_lookup(vec3 N, vec3 V, float alpha, out vec3 ab)
{
    float NdotV = dot(N, V);
    vec3 R = normalize(N * (2.0 * NdotV) - V);
    float r = splitsum_width(alpha);
    float lod = r * uSplitSumMaxLod;
    int set = sl_lobe_is_ggx(alpha) ? SPLITSUM_GGX : uGTerm == GTERM_INV_LH2 ? SPLITSUM_PHONG_INV_LH2 : SPLITSUM_PHONG_ONE;
    ab = splitsum_lut(set, NdotV, r).xyz;
    vec2 uv = sl_dir_to_uv(splitsum_dir(N, R, ab.z));
    return sl_lobe_is_ggx(alpha) ? textureLod(uSplitSumGGX, uv, lod).rgb : textureLod(uSplitSumPhong, uv, lod).rgb;
}

// Split sum (Karis 2013): the prefiltered environment along the lobe's centroid at the lobe's
// level, times the BRDF's albedo Ks A + B. No samples; N = V = R is the prefilter's assumption.
vec3 specular_splitsum(vec3 N, vec3 V, vec3 Ks, float alpha)
{
    vec3 ab;
    vec3 P = splitsum_lookup(N, V, alpha, ab);
    return P * (Ks * ab.x + ab.y) * uEnvIntensity;
}

// Level `level` of a chain read with the Catmull-Rom filter (src/ibl/texture_lod.h
// sl_env_catmull_rom): 4 x 4 texels about uv, REPEAT in u, and in v a row past a pole is the row
// beside it half a turn away. The exact levels are exact at their texel centres; this filter
// passes through them with a third-order error between them, where the bilinear one has a
// second-order one, which on the widest lobes' coarse levels is a percent.
vec3 chain_catmull_rom(bool ggx, int level, vec2 uv)
{
    // level 0's size halved `level` times, GL's mip sizes: llvmpipe's textureSize gave level 0's
    // size for a level that is not a constant
    ivec2 size = ggx ? textureSize(uSplitSumGGX, 0) : textureSize(uSplitSumPhong, 0);
    int w = max(size.x >> level, 1), h = max(size.y >> level, 1);
    float x = uv.x * float(w) - 0.5, y = uv.y * float(h) - 0.5;
    if (!(x > -2.0 && x < float(w) + 1.0 && y > -2.0 && y < float(h) + 1.0))
        return vec3(0.0);
    int i = int(floor(x)), j = int(floor(y));
    float tx = x - float(i), ty = y - float(j);
    vec4 wx = vec4(((-0.5 * tx + 1.0) * tx - 0.5) * tx, (1.5 * tx - 2.5) * tx * tx + 1.0,
                   ((-1.5 * tx + 2.0) * tx + 0.5) * tx, (0.5 * tx - 0.5) * tx * tx);
    vec4 wy = vec4(((-0.5 * ty + 1.0) * ty - 0.5) * ty, (1.5 * ty - 2.5) * ty * ty + 1.0,
                   ((-1.5 * ty + 2.0) * ty + 0.5) * ty, (0.5 * ty - 0.5) * ty * ty);
    ivec4 cols, turned;
    for (int a = 0; a < 4; a++) {
        int col = i - 1 + a;
        while (col < 0)
            col += w;
        while (col >= w)
            col -= w;
        cols[a] = col;
        int t = col + w / 2;
        turned[a] = t >= w ? t - w : t;
    }
    vec3 sum = vec3(0.0);
    for (int b = 0; b < 4; b++) {
        int row = j - 1 + b;
        bool past = row < 0 || row > h - 1;
        if (past) {
            row = row < 0 ? -row - 1 : 2 * h - row - 1;
            row = clamp(row, 0, h - 1);
        }
        vec3 r = vec3(0.0);
        for (int a = 0; a < 4; a++) {
            ivec2 t = ivec2(past ? turned[a] : cols[a], row);
            r += (ggx ? texelFetch(uSplitSumGGX, t, level).rgb : texelFetch(uSplitSumPhong, t, level).rgb) * wx[a];
        }
        sum += r * wy[b];
    }
    return sum;
}

// The control variate's kernel for the pixel (docs/lighting.md "Control variate"). The chain's
// exact levels hold the integral of the environment against a known kernel k about the lookup
// direction, so with K = ca k_a + cb k_b the exact part of the read and E = Ks A + B the albedo,
//     integral of f (N.w) L = beta E (ca C_a + cb C_b) + integral of (f (N.w) - beta E K) L.
// This is what the samples subtract: the kernel's axis, levels and shares, and beta E.
CvKernel cv_setup(vec3 N, vec3 V, vec3 Ks, float alpha)
{
    CvKernel cv;
    float NdotV = dot(N, V);
    vec3 R = normalize(N * (2.0 * NdotV) - V);
    float r = splitsum_width(alpha);
    float lod = r * uSplitSumMaxLod;
    cv.set = sl_lobe_is_ggx(alpha) ? SPLITSUM_GGX : uGTerm == GTERM_INV_LH2 ? SPLITSUM_PHONG_INV_LH2 : SPLITSUM_PHONG_ONE;
    vec4 lut = splitsum_lut(cv.set, NdotV, r);
    cv.on = true;
    cv.dir = splitsum_dir(N, R, lut.z);
    cv_levels(lod, cv);
    cv.scale = (Ks * lut.x + lut.y) * lut.w;
    return cv;
}

// The first term, beta E (ca C_a + cb C_b), times the intensity: the chain read along the
// kernel's axis at its two levels with the Catmull-Rom filter.
vec3 cv_closed(CvKernel cv)
{
    vec2 uv = sl_dir_to_uv(cv.dir);
    vec3 C = vec3(0.0);
    if (cv.ca > 0.0)
        C += cv.ca * chain_catmull_rom(cv.set == SPLITSUM_GGX, cv.la, uv);
    if (cv.cb > 0.0)
        C += cv.cb * chain_catmull_rom(cv.set == SPLITSUM_GGX, cv.lb, uv);
    return cv.scale * C * uEnvIntensity;
}

// The split sum as a control variate (uEstimator 6, and 7 with mis): the closed part plus the
// samples' estimate of the rest, the microfacet estimator's, 1/N sum (F W - beta E K / p) Li, or
// with mis (cvmis) mis's pairs, each sample's (f (N.w) - beta E K) Li / p times its
// power-heuristic weight. The subtracted kernel follows L across the lobe, so where beta E K is
// close to the lobe f (N.w) the samples pay only for the difference; beta scales the kernel down
// where it is not. Any beta leaves the expectation where the samples' estimator has it. With mis
// the environment's draws find the small bright sources that the BRDF's miss, and the kernel
// takes the smooth rest off both.
vec3 specular_cv(vec3 N, vec3 V, vec3 Ks, float alpha, vec2 rotation, bool mis)
{
    CvKernel cv = cv_setup(N, V, Ks, alpha);
    return cv_closed(cv) + (mis ? specular_mis(N, V, Ks, alpha, rotation, cv)
                                : specular_microfacet(N, V, Ks, alpha, rotation, cv));
}

// Env lights near a narrow lobe's peak (src/core/options.h SL_TEXEL_SPLIT_*, the ground truth's
// rule): where the lobe is narrower than a few texels (a sharp lobe, or any lobe seen at a grazing
// angle), one node a texel misses or overshoots its peak, so a light's texel near R is read over
// cells. Reflected about a facet spread by a (the lobe's width in H: GGX's a, or the Phong
// exponent's of equal peak), R spreads 2 a in the plane of N and V (along B) and 2 a N.V across
// it (along T), and the G term changes on a scale of N.V (L.H and L.N are about N.V near R at
// grazing): the cells' widths 2 a N.V and 2 min(a, N.V); which lights are near is measured
// against the lobe's own widths, 2 a N.V and 2 a. Each side of the texel gets as many cells as
// the lobe's width across it asks.
const int TEXEL_SPLIT_CELLS_PER_WIDTH = 8;
const int TEXEL_SPLIT_MAX = 16;
const float TEXEL_SPLIT_MIN_NV = 0.02;
const int ENV_LIGHT_NEAR_WIDTHS = 3;

struct EnvLightSplit {
    int cells;      // the most cells a side any texel needs (1: no light is split)
    float cosNear;  // a light with R.l at most this is not near
    vec3 R, T, B;   // R and the lobe's axes across it
    float across, along;       // the cells' widths along T and B
    float reach, side;         // the lobe's own along B (the near test's), the texel's longest side
};

EnvLightSplit env_light_split(vec3 N, vec3 V, float alpha)
{
    float a = sl_lobe_is_ggx(alpha) ? sqrt(sl_ggx_a2(alpha)) : sqrt(2.0 / (alpha + 2.0));
    float NdotV = dot(N, V);
    EnvLightSplit s;
    float nv = clamp(NdotV, TEXEL_SPLIT_MIN_NV, 1.0);
    s.across = 2.0 * a * nv;
    s.along = 2.0 * min(a, nv);
    s.reach = 2.0 * a;
    s.R = 2.0 * NdotV * N - V;
    vec3 T = cross(N, V); // N = V: the lobe is round, any T across R serves
    float t = length(T);
    vec3 other = abs(s.R.z) < 0.9 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
    s.T = t > 1e-6 ? T / t : normalize(cross(s.R, other));
    s.B = cross(s.R, s.T);
    s.side = uEnvLightSide;
    s.cells = int(min(ceil(float(TEXEL_SPLIT_CELLS_PER_WIDTH) * uEnvLightSide / s.across), float(TEXEL_SPLIT_MAX)));
    s.cosNear = cos(min(float(ENV_LIGHT_NEAR_WIDTHS) * s.reach + 2.0 * uEnvLightSide, PI));
    return s;
}

// The BRDF (2) at unit w times w.N: 0 below the horizon and for facets facing away (N.H <= 0).
vec3 env_light_brdf(vec3 w, vec3 N, vec3 V, vec3 Ks, float alpha)
{
    float wN = dot(w, N);
    if (wN <= 0.0)
        return vec3(0.0);
    vec3 H = normalize(w + V);
    float NdotH = dot(N, H);
    if (NdotH <= 0.0)
        return vec3(0.0);
    float LdotH = dot(w, H);
    float G = sl_lobe_G(LdotH, wN, dot(N, V), alpha, uGTerm);
    return sl_brdf_F(Ks, LdotH) * (sl_lobe_D(NdotH, alpha) * G / 4.0 * wN);
}

// Whether light direction l's texel lies within ENV_LIGHT_NEAR_WIDTHS of the lobe's widths of R
// (2 a N.V across, 2 a along) along both of its axes, give or take two texels (the offset l - R
// in radians, near R).
bool env_light_near(EnvLightSplit s, vec3 l)
{
    if (s.cells <= 1 || dot(s.R, l) <= s.cosNear)
        return false;
    vec3 q = l - s.R;
    float t = max(abs(dot(q, s.T)) - 2.0 * s.side, 0.0) / s.across;
    float b = max(abs(dot(q, s.B)) - 2.0 * s.side, 0.0) / s.reach;
    return t * t + b * b < float(ENV_LIGHT_NEAR_WIDTHS * ENV_LIGHT_NEAR_WIDTHS);
}

// The cells a texel side of length `side` along unit e needs, 1 .. TEXEL_SPLIT_MAX.
int env_light_cells_along(EnvLightSplit s, vec3 e, float side)
{
    float t = dot(e, s.T) / s.across, b = dot(e, s.B) / s.along;
    return int(clamp(ceil(float(TEXEL_SPLIT_CELLS_PER_WIDTH) * side * sqrt(t * t + b * b)), 1.0,
                     float(TEXEL_SPLIT_MAX)));
}

// The rows and columns of cells env light j's texel is split into: as many along each of its sides
// (its centroid's south and east) as the lobe's width across that side asks.
ivec2 env_light_grid(int j, EnvLightSplit s)
{
    vec3 c = uEnvLightDir[j].xyz;
    float st = max(sqrt(c.x * c.x + c.y * c.y), 1e-6); // sin(theta) of the centroid
    vec3 east = vec3(-c.y / st, c.x / st, 0.0), south = vec3(c.z * c.x / st, c.z * c.y / st, -st);
    return ivec2(env_light_cells_along(s, south, uEnvLightMeridian),
                 env_light_cells_along(s, east, abs(uEnvLightAzimuth) * st));
}

// Env light j's texel split into cells of equal solid angle (z = cos(theta) and phi uniform over
// its box), the BRDF times the cosine read at each cell's middle, each cell weighing its share of
// the texel's solid angle over its node weight (the radiance carries the node weight).
vec3 env_light_cells(int j, vec3 N, vec3 V, vec3 Ks, float alpha, EnvLightSplit s)
{
    vec4 box = uEnvLightTexel[j];
    ivec2 grid = env_light_grid(j, s);
    int rows = grid.x, cols = grid.y;
    if (rows * cols == 1) // the centroid, the better node
        return env_light_brdf(uEnvLightDir[j].xyz, N, V, Ks, alpha);
    vec3 sum = vec3(0.0);
    for (int b = 0; b < rows; b++) {
        float z = mix(box.x, box.y, (float(b) + 0.5) / float(rows));
        float sz = sqrt(max(1.0 - z * z, 0.0));
        for (int a = 0; a < cols; a++) {
            float phi = box.z + uEnvLightAzimuth * (float(a) + 0.5) / float(cols);
            sum = sum + env_light_brdf(vec3(cos(phi) * sz, sin(phi) * sz, z), N, V, Ks, alpha);
        }
    }
    return sum * (uEnvLightRadiance[j].a / float(rows * cols));
}

// Env lights: each is one texel's quadrature node (its centroid direction w, its radiance times
// the node weight), so this is the ground truth's sum over those texels: the BRDF (2) at w,
// times w.N, or over the texel's cells near a narrow lobe's peak (env_light_split); 0 for a light
// below the horizon or under the facet (facet_hides). Environment space.
// shadowed: each light times vis[j], its visibility in its shadow map (env_light_visibility);
// otherwise vis is not read.
vec3 specular_env_lights(vec3 N, vec3 V, vec3 Ks, float alpha, bool shadowed, float vis[MAX_ENV_LIGHTS])
{
    EnvLightSplit split = env_light_split(N, V, alpha);
    vec3 sum = vec3(0.0);
    for (int j = 0; j < uEnvLightCount; j++) {
        vec3 w = uEnvLightDir[j].xyz;
        if (dot(w, N) <= 0.0 || facet_hides(w)) // a light under the facet: its centroid's
            continue;
        vec3 f = env_light_near(split, w) ? env_light_cells(j, N, V, Ks, alpha, split)
                                          : env_light_brdf(w, N, V, Ks, alpha);
        float v = shadowed ? vis[j] : 1.0; // x 1 is exact: without maps, the same bits
        sum = sum + f * uEnvLightRadiance[j].rgb * v;
    }
    return sum * uEnvIntensity;
}

// Visibility of env-light map s (below, beside the cube maps' lookup, as in src/shadow/shadow.c).
float shadow_sun_visibility(int s, vec3 P, vec3 N);

// Each env light's visibility from world point P with normal N: that of its map, 1 for a light
// no map covers, 0 past the count, and each map's in gGlowVis (glow). One lookup per map.
void env_light_visibility(vec3 P, vec3 N, out float vis[MAX_ENV_LIGHTS])
{
    float map_vis[SHADOW_SUN_MAX];
    for (int k = 0; k < uShadowSunCount; k++)
        map_vis[k] = shadow_sun_visibility(k, P, N);
    for (int k = 0; k < SHADOW_SUN_MAX; k++) // the glow's (glow)
        gGlowVis[k] = k < uShadowSunCount ? map_vis[k] : 0.0;
    for (int j = 0; j < MAX_ENV_LIGHTS; j++) {
        int k = j < uEnvLightCount ? uEnvLightSun[j] : -2;
        vis[j] = k >= 0 ? map_vis[k] : k == -1 ? 1.0 : 0.0;
    }
}

// The env lights' part of the irradiance E(N) (N in environment space): sum L_k max(N.l_k, 0)
// over every light (all: what the irradiance holds) and times each one's visibility (seen).
void env_lights_irradiance(vec3 N, float vis[MAX_ENV_LIGHTS], out vec3 all, out vec3 seen)
{
    vec3 a = vec3(0.0), s = vec3(0.0);
    for (int j = 0; j < uEnvLightCount; j++) {
        float c = max(dot(uEnvLightDir[j].xyz, N), 0.0);
        vec3 L = uEnvLightRadiance[j].rgb * c;
        a = a + L;
        s = s + L * vis[j];
    }
    all = a;
    seen = s;
}

// One point light with the full BRDF (2): f * color * intensity / d^2 * max(N.L, 0); world space.
vec3 point_light(int i, vec3 P, vec3 N, vec3 V, vec3 Kd, vec3 Ks, float alpha)
{
    vec3 toLight = uLightPosition[i] - P;
    float d2 = dot(toLight, toLight);
    if (d2 < MIN_LIGHT_D2)
        return vec3(0.0);
    vec3 L = toLight * (1.0 / sqrt(d2));
    float NdotL = dot(N, L);
    if (NdotL <= 0.0)
        return vec3(0.0);
    vec3 H = normalize(L + V);
    float LdotH = dot(L, H);
    vec3 f = vec3(0.0);
    if (uDiffuse != 0)
        f = f + Kd * (1.0 / PI);
    if (uSpecular != 0) {
        float G = sl_lobe_G(LdotH, NdotL, dot(N, V), alpha, uGTerm);
        f = f + sl_brdf_F(Ks, LdotH) * (sl_lobe_D(dot(N, H), alpha) * G / 4.0);
    }
    return f * uLightColor[i] * (uLightIntensity[i] / d2 * NdotL);
}

// The frame of cube face f (shadow.c face_frames): the axis it looks along, its x and its y.
void shadow_face_frame(int f, out vec3 ax, out vec3 rt, out vec3 up)
{
    ax = vec3(0.0);
    ax[f / 2] = (f % 2) == 0 ? 1.0 : -1.0;
    vec3 up0 = f >= 4 ? vec3(0.0, 1.0, 0.0) : vec3(0.0, 0.0, 1.0);
    rt = normalize(cross(ax, up0));
    up = cross(rt, ax);
}

// The face whose axis is d's major axis, ties to the earlier face (shadow.c major_face).
int shadow_major_face(vec3 d)
{
    float ax = abs(d.x), ay = abs(d.y), az = abs(d.z);
    if (ax >= ay && ax >= az)
        return d.x >= 0.0 ? 0 : 1;
    if (ay >= az)
        return d.y >= 0.0 ? 2 : 3;
    return d.z >= 0.0 ? 4 : 5;
}

// The normal offset's share of its full length for a receiver whose normal makes cosine c with
// the direction to the light: the sine (src/shadow/shadow.h sl_shadow_offset_share, which says
// why). Every lookup below takes it.
float shadow_offset_share(float c)
{
    return sqrt(max(1.0 - c * c, 0.0));
}

// Visibility of point light i from P with unit normal N in its cube map (the twin of
// sl_shadow_point_visibility, src/shadow/shadow.c, whose comments say why each step): 1 lit,
// 0 shadowed; the receiver moved along N by up to one texel's footprint, then a 3-texel box of
// bilinear comparisons over the 4x4 texels around it, each tap against the depth at which its
// own ray meets the receiver's plane, less a constant bias.
float shadow_point_visibility(int i, vec3 P, vec3 N)
{
    int layer = uShadowCubeLayer[i];
    if (layer < 0)
        return 1.0;
    vec3 d = P - uLightPosition[i];
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0))
        return 1.0;
    float dist = sqrt(dist2);
    float texel = 2.0 * dist / float(SHADOW_CUBE_SIZE);
    vec3 q = d + N * (texel * SHADOW_NORMAL_OFFSET * shadow_offset_share(dot(N, d) / dist));
    int f = shadow_major_face(q);
    vec3 ax, rt, up;
    shadow_face_frame(f, ax, rt, up);
    float z = dot(q, ax);
    if (!(z > 0.0))
        return 1.0;
    int sideI = SHADOW_CUBE_SIZE + 2 * SHADOW_GUARD;
    float side = float(sideI);
    float proj = float(SHADOW_CUBE_SIZE) / side;
    float ux = (proj * dot(q, rt) / z + 1.0) * 0.5 * side - 0.5;
    float uy = (proj * dot(q, up) / z + 1.0) * 0.5 * side - 0.5;
    float fx = floor(ux), fy = floor(uy);
    float tx = ux - fx, ty = uy - fy;
    int x0 = int(fx) - 1, y0 = int(fy) - 1;
    float nq = dot(N, q), na = dot(N, ax), nr = dot(N, rt), nu = dot(N, up);
    float step = 2.0 / (side * proj);
    float cx0 = (float(x0) + 0.5) * step - 1.0 / proj, cy0 = (float(y0) + 0.5) * step - 1.0 / proj;
    float bias = texel * SHADOW_BIAS_CONST;
    float wx[4] = float[4]((1.0 - tx) / 3.0, 1.0 / 3.0, 1.0 / 3.0, tx / 3.0);
    float wy[4] = float[4]((1.0 - ty) / 3.0, 1.0 / 3.0, 1.0 / 3.0, ty / 3.0);
    int last = sideI - 1;
    float vis = 0.0;
    for (int b = 0; b < 4; b++) {
        int y = clamp(y0 + b, 0, last);
        float ny = na + nu * (cy0 + float(b) * step);
        float rv = 0.0;
        for (int a = 0; a < 4; a++) {
            int x = clamp(x0 + a, 0, last);
            float nd = ny + nr * (cx0 + float(a) * step);
            float stored = texelFetch(uShadowCubes, ivec3(x, y, layer + f), 0).r;
            bool open = nd > -1e-6 || (stored * (1.0 + SHADOW_DEPTH_REL) + bias) * nd <= nq;
            rv += open ? wx[a] : 0.0;
        }
        vis += rv * wy[b];
    }
    return min(vis, 1.0);
}

// Visibility of env-light map s from world point P with unit normal N (the twin of
// sl_shadow_sun_visibility, src/shadow/shadow.c, whose comments say why each step): 1 lit, 0
// shadowed, 1 for a normal facing away from the lights; the receiver moved along N by up to one
// texel, then the cube maps' 3-texel box of bilinear comparisons, each tap against the
// receiver plane's depth under it less a constant bias.
float shadow_sun_visibility(int s, vec3 P, vec3 N)
{
    if (s < 0 || s >= uShadowSunCount)
        return 1.0;
    vec3 axis = uShadowSunAxis[s], right = uShadowSunRight[s], up = uShadowSunUp[s];
    vec4 box = uShadowSunBox[s]; // x0, y0, sx, sy
    float sz = uShadowSunDepth[s].x, texel = uShadowSunDepth[s].y;
    float na = dot(N, axis);
    if (!(na < -1e-6))
        return 1.0;
    float size = float(SHADOW_SUN_SIZE);
    vec3 q = P + N * (texel * SHADOW_NORMAL_OFFSET * shadow_offset_share(na));
    float xq = dot(q, right), yq = dot(q, up), zq = dot(q, axis);
    float stepx = box.z / size, stepy = box.w / size;
    float ux = (xq - box.x) / stepx - 0.5, uy = (yq - box.y) / stepy - 0.5;
    float fx = floor(ux), fy = floor(uy);
    if (!(abs(fx) < 1e6 && abs(fy) < 1e6))
        return 1.0;
    float tx = ux - fx, ty = uy - fy;
    int x0 = int(fx) - 1, y0 = int(fy) - 1;
    float gx = -dot(N, right) / na, gy = -dot(N, up) / na;
    float bias = texel * SHADOW_BIAS_CONST + sz * 1e-6;
    float wx[4] = float[4]((1.0 - tx) / 3.0, 1.0 / 3.0, 1.0 / 3.0, tx / 3.0);
    float wy[4] = float[4]((1.0 - ty) / 3.0, 1.0 / 3.0, 1.0 / 3.0, ty / 3.0);
    int last = SHADOW_SUN_SIZE - 1;
    float vis = 0.0;
    for (int b = 0; b < 4; b++) {
        int y = clamp(y0 + b, 0, last);
        float dy = (float(y0 + b) + 0.5) * stepy + box.y - yq;
        float rv = 0.0;
        for (int a = 0; a < 4; a++) {
            int x = clamp(x0 + a, 0, last);
            float dx = (float(x0 + a) + 0.5) * stepx + box.x - xq;
            float receiver = zq + gx * dx + gy * dy;
            float stored = texelFetch(uShadowSuns, ivec3(x, y, s), 0).r;
            rv += stored + bias >= receiver ? wx[a] : 0.0;
        }
        vis += rv * wy[b];
    }
    return min(vis, 1.0);
}

// Visibility of sky map k from world point P with unit normal N (the twin of
// sl_shadow_sky_map_visibility, src/shadow/sky.c, whose comments say why each step): 1 open, 0
// hidden, 1 where the map's direction is below P's plane; the receiver moved along N by up to one
// texel, then a 2x2 bilinear percentage-closer lookup, each tap against the receiver plane's
// depth under it less a constant bias.
float sky_map_visibility(int k, vec3 P, vec3 N)
{
    vec3 axis = uSkyMapAxis[k], right = uSkyMapRight[k], up = uSkyMapUp[k];
    vec4 box = uSkyMapBox[k]; // x0, y0, sx, sy
    float sz = uSkyMapDepth[k].x, texel = uSkyMapDepth[k].y;
    float na = dot(N, axis);
    if (!(na < -1e-6))
        return 1.0;
    int sizeI = textureSize(uSkyMaps, 0).x;
    float size = float(sizeI);
    vec3 q = P + N * (texel * SKY_NORMAL_OFFSET * shadow_offset_share(na));
    float xq = dot(q, right), yq = dot(q, up), zq = dot(q, axis);
    float stepx = box.z / size, stepy = box.w / size;
    float ux = (xq - box.x) / stepx - 0.5, uy = (yq - box.y) / stepy - 0.5;
    float fx = floor(ux), fy = floor(uy);
    if (!(abs(fx) < 1e6 && abs(fy) < 1e6))
        return 1.0;
    float tx = ux - fx, ty = uy - fy;
    int x0 = int(fx), y0 = int(fy);
    float gx = -dot(N, right) / na, gy = -dot(N, up) / na;
    float bias = texel * SKY_BIAS_CONST + sz * 1e-6;
    float wx[2] = float[2](1.0 - tx, tx);
    float wy[2] = float[2](1.0 - ty, ty);
    int last = sizeI - 1;
    float vis = 0.0;
    for (int b = 0; b < 2; b++) {
        int y = clamp(y0 + b, 0, last);
        float dy = (float(y0 + b) + 0.5) * stepy + box.y - yq;
        for (int a = 0; a < 2; a++) {
            int x = clamp(x0 + a, 0, last);
            float dx = (float(x0 + a) + 0.5) * stepx + box.x - xq;
            float receiver = zq + gx * dx + gy * dy;
            float stored = texelFetch(uSkyMaps, ivec3(x, y, k), 0).r;
            vis += stored + bias >= receiver ? wx[a] * wy[b] : 0.0;
        }
    }
    return min(vis, 1.0);
}

// V at world point P with unit normal N (the twin of sl_shadow_sky_visibility, src/shadow/sky.c):
// each map's visibility weighted by max(N.m_k, 0), a map of weight 0 not read; 1 where no map
// weighs anything.
float sky_visibility(vec3 P, vec3 N)
{
    float seen = 0.0, all = 0.0;
    for (int k = 0; k < uSkyMapCount; k++) {
        float w = max(dot(N, uSkyMapWeight[k]), 0.0);
        if (w > 0.0) {
            float v = sky_map_visibility(k, P, N);
            seen += v * w;
            all += w;
        }
    }
    return all > 0.0 ? seen / all : 1.0;
}

// The cell holding direction d (environment space, unit; the twin of sl_shadow_sky_cell): the
// nearest site on d's side of the horizon, or the nearest of all when that side has none.
int sky_cell(vec3 d)
{
    int first = 0, last = uSkyMapCount;
    if (uSkyMapCount > uSkyCellSkySites) {
        first = d.z >= 0.0 ? 0 : uSkyCellSkySites;
        last = d.z >= 0.0 ? uSkyCellSkySites : uSkyMapCount;
    }
    int best = first;
    float bestDot = -2.0;
    for (int k = first; k < last; k++) {
        float c = dot(d, uSkyCellSite[k]);
        if (c > bestDot) {
            bestDot = c;
            best = k;
        }
    }
    return best;
}

// The part across the horizon (gHorizonSum) times the visibility from P (world, N the world
// normal) of the map whose cell holds its luminous direction; 0 with nothing across.
vec3 horizon_visible(vec3 P, vec3 N)
{
    float len = length(gHorizonDir);
    if (!(len > 0.0))
        return vec3(0.0);
    return gHorizonSum * sky_map_visibility(sky_cell(gHorizonDir / len), P, N);
}

// With the sky maps' part across the horizon, the share of the cone's occlusion across the
// horizon from R, in [0, 1]: the cone's axis B leans away from its occluders, and the share of
// the lean B - N that points across from R's side is taken as theirs. The maps take that part of
// the lobe, so the specular occlusion opens the cone's AO by it; 0 without the maps.
float cone_across(vec3 B, vec3 N, vec3 R)
{
    vec3 lean = B - N;
    float len = length(lean);
    float up = len > 1e-6 ? lean.z / len : 0.0;
    float across = R.z >= 0.0 ? up : -up;
    return horizon_on() ? clamp(across, 0.0, 1.0) : 0.0;
}

// With the sky maps, a lobe at least LOBE_MAP_SHARE of a cell wide (its cone's angle ts at least
// that share of uSkyCellAngle, the angle of a cap of 4 pi / K steradians) also takes the
// visibility of the map whose cell holds R, times the material's occlusion: the specular's
// factor is the smaller of `capped` and that (the rays see only what the G-buffer holds; the map
// sees the whole scene). R in environment space, P and N in the world.
float lobe_map_factor(float capped, float material, vec3 P, vec3 N, vec3 R, float alpha)
{
    if (!(SL_SKY_MAPS != 0 && uSkyMapCount > 0) || so_acos(so_lobe_cos(alpha)) < LOBE_MAP_SHARE * uSkyCellAngle)
        return capped;
    return min(capped, material * sky_map_visibility(sky_cell(R), P, N));
}

// point_light times the light's visibility from P in its shadow map, looked up only where the
// light adds something.
vec3 shadowed_point_light(int i, vec3 P, vec3 N, vec3 V, vec3 Kd, vec3 Ks, float alpha)
{
    vec3 light = point_light(i, P, N, V, Kd, Ks, alpha);
    if (SL_SHADOW_CUBES != 0 && (light.x > 0.0 || light.y > 0.0 || light.z > 0.0))
        light = light * shadow_point_visibility(i, P, N);
    return light;
}

// A pixel with no geometry shows the environment at lod 0 in the view direction: the ray
// through the pixel centre from the near to the far plane.
vec3 background(vec2 fragCoord)
{
    vec2 ndc = 2.0 * fragCoord / uViewport - 1.0;
    vec4 nearP = uInvViewProj * vec4(ndc, -1.0, 1.0);
    vec4 farP = uInvViewProj * vec4(ndc, 1.0, 1.0);
    vec3 d = normalize(farP.xyz * (1.0 / farP.w) - nearP.xyz * (1.0 / nearP.w));
    return textureLod(uEnv, sl_dir_to_uv(uEnvRotation * d), 0.0).rgb * uEnvIntensity;
}

void main()
{
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    float depth = texelFetch(uDepth, pixel, 0).r;
    vec3 color = vec3(0.0);
    if (depth >= 1.0) {
        color = background(gl_FragCoord.xy);
    } else {
        vec3 P = texelFetch(uPosition, pixel, 0).xyz;
        vec3 Kd = texelFetch(uKd, pixel, 0).rgb;
        vec4 KsAlpha = texelFetch(uKsAlpha, pixel, 0);
        vec3 Ks = KsAlpha.rgb;
        float alpha = lobe_param(KsAlpha.a);
        vec3 V = normalize(uEye - P);
        vec3 N = facing_normal(texelFetch(uNormal, pixel, 0).xyz, V);
        vec3 Nenv = uEnvRotation * N;
        vec3 Venv = uEnvRotation * V;
        vec3 Fenv = facet_env(pixel);
        vec2 rotation = uRotate != 0 ? pixel_rotation(pixel) : vec2(0.0, 0.0);
        vec4 extra = uHasExtra != 0 ? texelFetch(uExtra, pixel, 0) : vec4(1.0, 0.0, 0.0, 0.0);
        // With the env lights' shadow maps: each env light's visibility from P; the lights' part
        // of the irradiance is taken out of E (clamped: a smoothing irradiance can put a sun's
        // lobe where E is below it) and added back times the visibility, the specular's exact
        // part is times it too; both are added after the occlusion, as the point lights are.
        bool envShadow = SL_SHADOW_SUNS != 0 && uShadowSunCount > 0;
        float envVis[MAX_ENV_LIGHTS];
        vec3 envAll = vec3(0.0), shadowedLights = vec3(0.0);
        if (envShadow) {
            env_light_visibility(P, N, envVis);
            if (uDiffuse != 0) {
                vec3 seen;
                env_lights_irradiance(Nenv, envVis, envAll, seen);
                shadowedLights = Kd * (1.0 / PI) * seen * uEnvIntensity;
            }
        }
        // With the sky visibility maps: their V on the residual's irradiance (the env lights'
        // part, added back after the occlusion, has its own maps); with the cone they replace
        // the AO on the diffuse (read about N, times the material's occlusion alone)
        bool skyMaps = SL_SKY_MAPS != 0 && uSkyMapCount > 0;
        // The reflection occlusion: with the cone it joins the specular's factor by its rays'
        // count, without it scales the specular
        bool reflection = uReflectionDistance > 0.0;
        vec2 reflectionVis = reflection ? reflection_visibility(pixel) : vec2(1.0, 0.0);
        if (uHasCone == 0) {
            if (uDiffuse != 0) {
                vec3 E = envShadow ? max(irradiance(Nenv) - envAll, vec3(0.0)) : irradiance(Nenv);
                if (skyMaps)
                    E = E * sky_visibility(P, N);
                color = color + Kd * (1.0 / PI) * E * uEnvIntensity;
            }
            if (uSpecular != 0) {
                vec3 spec;
                horizon_for(Nenv, Venv, Fenv);
                glow_for(envShadow);
                int estimator = estimator_of(alpha);
                if (estimator == ESTIMATOR_SPLITSUM)
                    spec = specular_splitsum(Nenv, Venv, Ks, alpha);
                else if (estimator == ESTIMATOR_MICROFACET)
                    spec = specular_microfacet(Nenv, Venv, Ks, alpha, rotation, no_cv());
                else if (estimator == ESTIMATOR_CV || estimator == ESTIMATOR_CV_MIS)
                    spec = specular_cv(Nenv, Venv, Ks, alpha, rotation, estimator == ESTIMATOR_CV_MIS);
                else if (estimator == ESTIMATOR_MIS)
                    spec = specular_mis(Nenv, Venv, Ks, alpha, rotation, no_cv());
                else
                    spec = specular_ibl(Nenv, Venv, Ks, alpha, rotation);
                if (SL_ENV_LIGHTS != 0 && env_lights_of(alpha) && !envShadow)
                    spec = spec + specular_env_lights(Nenv, Venv, Ks, alpha, false, envVis);
                // the part across the horizon: after the factor (the sum's occlusion below scales it)
                color = color + (spec * reflectionVis.x + horizon_visible(P, N));
            }
            color = color * extra.r; // occlusion: the image-based terms only
        } else {
            // the occlusion pass's cone: each image-based term times its own occlusion, the
            // diffuse read along the bent direction, the specular times the material's share of
            // the occlusion and specular_occlusion
            vec4 c = texelFetch(uCone, pixel, 0);
            vec3 B = uEnvRotation * c.xyz;
            vec3 R = Nenv * (2.0 * dot(Nenv, Venv)) - Venv;
            float so = specular_occlusion(c.w + (1.0 - c.w) * cone_across(B, Nenv, R), dot(B, R), dot(Nenv, Venv), alpha);
            float spec_occlusion = c.w > 0.0 ? extra.r * (so / c.w) : 0.0;
            // the material's share of the occlusion: the reflection join's and the part across
            // the horizon's
            float materialOcclusion = c.w > 0.0 ? extra.r / c.w : 0.0;
            if (reflection)
                spec_occlusion = reflection_specular_factor(spec_occlusion, materialOcclusion, reflectionVis);
            spec_occlusion = lobe_map_factor(spec_occlusion, materialOcclusion, P, N, R, alpha);
            if (uDiffuse != 0) {
                // the irradiance along the bent direction; with the env lights' maps, their
                // part of it taken out along the same direction (the maps add it back about N)
                vec3 D = skyMaps ? Nenv : bent_irradiance_dir(Nenv, B, c.w);
                vec3 E = irradiance(D);
                if (envShadow) {
                    vec3 unused;
                    env_lights_irradiance(D, envVis, envAll, unused);
                    E = max(E - envAll, vec3(0.0));
                }
                float diffuseOcclusion = extra.r;
                if (skyMaps) {
                    E = E * sky_visibility(P, N);
                    diffuseOcclusion = c.w > 1e-3 ? min(extra.r / c.w, 1.0) : 1.0;
                }
                color = color + Kd * (1.0 / PI) * E * uEnvIntensity * diffuseOcclusion;
            }
            if (uSpecular != 0) {
                vec3 spec;
                horizon_for(Nenv, Venv, Fenv);
                glow_for(envShadow);
                int estimator = estimator_of(alpha);
                if (estimator == ESTIMATOR_SPLITSUM)
                    spec = specular_splitsum(Nenv, Venv, Ks, alpha);
                else if (estimator == ESTIMATOR_MICROFACET)
                    spec = specular_microfacet(Nenv, Venv, Ks, alpha, rotation, no_cv());
                else if (estimator == ESTIMATOR_CV || estimator == ESTIMATOR_CV_MIS)
                    spec = specular_cv(Nenv, Venv, Ks, alpha, rotation, estimator == ESTIMATOR_CV_MIS);
                else if (estimator == ESTIMATOR_MIS)
                    spec = specular_mis(Nenv, Venv, Ks, alpha, rotation, no_cv());
                else
                    spec = specular_ibl(Nenv, Venv, Ks, alpha, rotation);
                if (SL_ENV_LIGHTS != 0 && env_lights_of(alpha) && !envShadow)
                    spec = spec + specular_env_lights(Nenv, Venv, Ks, alpha, false, envVis);
                // the part across the horizon: after the factor, times the material's occlusion
                color = color + (spec * spec_occlusion + horizon_visible(P, N) * materialOcclusion);
            }
        }
        if (envShadow) {
            if (uSpecular != 0)
                shadowedLights = shadowedLights + specular_env_lights(Nenv, Venv, Ks, alpha, true, envVis);
            color = color + shadowedLights;
        }
        if (uPointLights != 0) {
            for (int i = 0; i < uLightCount; i++)
                color = color + shadowed_point_light(i, P, N, V, Kd, Ks, alpha);
        }
        if (uDiffuse != 0)
            color = color + extra.gba; // emission, view-independent: it travels with the diffuse term
    }
    bool finite = !any(isnan(color)) && !any(isinf(color));
    fragColor = finite ? vec4(color, 1.0) : vec4(0.0);
}
