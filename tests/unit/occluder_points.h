/* occluder_points.h - the occluder scene the shadow and sky-map lookup tests draw their maps over
 * (FX_OCCLUDER_SCENE: a floor 8 units wide, a unit sphere standing on it at (0.5, 0, 1), a box at
 * (-1.5, 1)), and points on and about it, each with a normal: the floor's, the sphere's, anywhere any way, and the floor by
 * the box edge-on; from a seeded generator of the tests' own, so a test's points are the same on
 * every run. Header-only (static inline functions): each test executable is one translation
 * unit. */
#ifndef OCCLUDER_POINTS_H
#define OCCLUDER_POINTS_H

#include <math.h>
#include <stdint.h>

#include "softlight/glsl.h"

/* The scene's text up to its objects' closing bracket: a test closes it ("}") or adds keys first
 * (lights). */
#define FX_OCCLUDER_SCENE \
    "{\"camera\": {\"eye\": [0, -8, 3], \"target\": [0, 0, 0.5]},\n" \
    " \"environment\": {\"hdr\": \"none.hdr\"},\n" \
    " \"materials\": {\"m\": {\"kd\": 0.5}},\n" \
    " \"objects\": [\n" \
    "  {\"shape\": \"plane\", \"material\": \"m\", \"transform\": {\"scale\": [4, 4, 1]}},\n" \
    "  {\"shape\": \"sphere\", \"material\": \"m\", \"transform\": {\"translate\": [0.5, 0, 1]}},\n" \
    "  {\"shape\": \"box\", \"material\": \"m\", \"transform\": {\"translate\": [-1.5, 1, 0.5]," \
    " \"rotate\": [0, 0, 1, 30], \"scale\": [0.5, 1.5, 1]}}\n" \
    " ]"

/* The generator's state (a linear congruential generator: the same sequence on every machine). */
typedef struct {
    uint32_t state;
} fx_rng;

/* A float in [0, 1). */
static inline float fx_rnd(fx_rng *r)
{
    r->state = r->state * 1664525u + 1013904223u;
    return (float)(r->state >> 8) / 16777216.0f;
}

/* A direction uniform over the sphere. */
static inline vec3 fx_rnd_dir(fx_rng *r)
{
    float z = 2.0f * fx_rnd(r) - 1.0f, phi = 2.0f * SL_PI * fx_rnd(r), s = sqrtf(fmaxf(1.0f - z * z, 0.0f));
    return vec3(s * cosf(phi), s * sinf(phi), z);
}

/* Point i of the scene into *P with its normal *N, by i mod 4: the floor, normal up (tilted now
 * and then); the sphere; anywhere about the scene, any way; the floor by the box, normals near the
 * horizon (edge-on to some maps). */
static inline void fx_occluder_point(fx_rng *r, int i, vec3 *P, vec3 *N)
{
    float u = 2.0f * fx_rnd(r) - 1.0f, v = 2.0f * fx_rnd(r) - 1.0f;
    switch (i % 4) {
    case 0:
        *P = vec3(4.0f * u, 4.0f * v, 0.0f);
        *N = i % 8 ? vec3(0, 0, 1) : normalize(add(vec3(0, 0, 1), scale(fx_rnd_dir(r), 0.3f)));
        break;
    case 1:
        *N = fx_rnd_dir(r);
        *P = add(vec3(0.5f, 0, 1), *N);
        break;
    case 2:
        *P = vec3(5.0f * u, 5.0f * v, 3.0f * fx_rnd(r) - 0.5f);
        *N = fx_rnd_dir(r);
        break;
    default:
        *P = vec3(-1.5f + 1.5f * u, 1.0f + 2.0f * v, 0.0f);
        *N = normalize(vec3(u, v, 0.02f * fx_rnd(r)));
        break;
    }
}

#endif
