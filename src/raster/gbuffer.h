/* gbuffer.h - the G-buffer: what rasterization leaves for the lighting stage.
 *
 * One texel per pixel, array of structs, ROW 0 IS THE BOTTOM ROW (OpenGL window
 * coordinates, DESIGN.md). The built-in fragment shader fills every field; the
 * lighting shader reads them and nothing else. Cleared per frame to depth = 1
 * (the far plane), which with the LESS test means "no geometry": the coverage
 * mask is exactly `depth < 1`. The vector toward the eye is not stored: it is
 * normalize(eye - position), derived where needed from the camera.
 *
 * 14 floats = 56 bytes per pixel (116 MB at 1920x1080; docs/gbuffer.md). */
#ifndef SL_GBUFFER_H
#define SL_GBUFFER_H

#include <stdbool.h>

#include "../core/error.h"
#include "../core/glsl.h"

typedef struct {
    vec3 position; /* world space */
    vec3 normal;   /* unit, world space */
    vec3 kd;       /* linear RGB diffuse albedo */
    vec3 ks;       /* linear RGB Schlick F0 */
    float alpha;   /* Phong exponent */
    float depth;   /* window depth in [0,1]; 1 = nothing drawn */
} sl_gbuffer_texel;

typedef struct {
    int width, height;
    sl_gbuffer_texel *texels; /* width * height, row 0 = bottom */
} sl_gbuffer;

static inline bool sl_gbuffer_covered(const sl_gbuffer_texel *t) { return t->depth < 1.0f; }

#endif
