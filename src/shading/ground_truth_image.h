/* ground_truth_image.h - the ground truth of a whole G-buffer: eq. (1) with the BRDF of eq. (2)
 * at every covered pixel, integrated over every texel of the environment (src/ibl/ground_truth.h),
 * with an on-disk cache and a progress callback. What accuracy reports and `softlight truth`
 * compare the lighting shader's images against. It is the exact counterpart of the lighting pass
 * (lighting.h), so it lives beside it in the shading stage: it reads a G-buffer (raster) and forms
 * N and V as the shader does; src/ibl holds only the per-direction integral it calls.
 *
 * Consumes: a G-buffer (row 0 = bottom), the eye, the environment and its rotation/intensity as
 * the lighting stage takes them (d_env = Rz(-rotation) d_world, radiance x intensity).
 * Produces: diffuse and specular radiance images, ROW 0 = TOP like the lighting stage's output,
 * 0 where nothing is drawn, the specular for BOTH G terms (1/(L.H)^2 and 1) from one pass over
 * the texels (the second G costs one more multiply-add per texel, not a second pass), and the
 * coverage mask. Image-based light only unless `lights` adds the scene's point lights; no
 * background. Blind by default, as the lighting shader is: every surface sees the whole
 * environment; `visibility` traces the scene's triangles (visibility.h) so occluders shadow it.
 *
 * Per pixel it integrates what the shader shades: V = normalize(eye - P) and N =
 * facing_normal(normal, V) computed in float exactly as lighting.frag does (a normal facing away
 * from the eye, N.V < 0.01, is bent to N.V = 0.01), alpha clamped to [0, 1e7] as the shader
 * clamps it. The result is sl_ground_truth_shade's for that (N, V), rounded to float (tested).
 *
 * Cache: one file, a text header a person can read with `head` (what made it: label, sizes,
 * hashes of the environment's level 0 and of every G-buffer texel, eye, rotation, intensity,
 * the integrator version; with visibility or lights also their settings, the hash of the
 * world-space triangles and the lights; and `key`, the FNV-1a 64 hash of all of those), then "data\n" and
 * the planes as little-endian float32. A cache file is used only when its key and size equal
 * those of the request; anything else is recomputed and the file rewritten (atomically).
 *
 * Threads: OpenMP over rows (dynamic); a pixel depends only on its texel, so the images are
 * bitwise identical for any thread count. Cost: about 5.6 ms per covered pixel per core for a
 * 1024x512 environment (docs/ibl.md). The progress callback runs on the calling thread. */
#ifndef SL_GROUND_TRUTH_IMAGE_H
#define SL_GROUND_TRUTH_IMAGE_H

#include <stdbool.h>
#include <stdint.h>

#include "../core/error.h"
#include "../core/image.h"
#include "../ibl/ground_truth.h"
#include "../ibl/ibl.h"
#include "../raster/gbuffer.h"
#include "../raster/gbuffer_textured.h"
#include "../scene/scene.h"

/* Pixels done of `total` (covered pixels); called from the calling thread, the last call
 * with done == total. */
typedef void (*sl_gt_progress_fn)(void *user, long done, long total);

typedef struct {
    const sl_env *env;         /* required; level 0 is integrated */
    const sl_gbuffer *gbuffer; /* required */
    vec3 eye;                  /* world space */
    float env_rotation_deg;    /* about +Z, as sl_lighting_options */
    float env_intensity;       /* multiplies the environment (explicit: 0 gives black) */
    int threads;               /* <= 0: OpenMP's default */
    const char *cache_path;    /* NULL: compute, write nothing */
    const char *label;         /* recorded in the cache header (e.g. the scene file); may be NULL */
    sl_gt_progress_fn progress; /* may be NULL */
    void *progress_user;
    /* Visibility (docs/ibl.md "Visibility"): each environment node's contribution times whether
     * P sees its direction past the scene's triangles (visibility.h), traced once per cell of
     * 2^visibility_level x 2^visibility_level level-0 texels at the centroid of the cell's nodes
     * that lie above both horizons (N's and the geometric normal's); nodes below the geometric
     * horizon are unseen. Off: the blind integral above, byte for byte. */
    const sl_scene *scene;      /* the occluders and point lights; required with visibility or lights */
    const sl_scene_textures *textures; /* the scene's images: masked casters occlude where their
                                          masks keep them (NULL: every caster opaque) */
    bool visibility;
    int visibility_level;       /* 0 .. SL_GT_VIS_LEVEL_MAX */
    /* The scene's point lights added as lighting.frag adds them (not scaled by the occlusion
     * map), each times a shadow ray to the light with visibility. Off: image-based light only. */
    bool lights;
} sl_gt_image_desc;

#define SL_GT_VIS_LEVEL_DEFAULT 3
#define SL_GT_VIS_LEVEL_MAX 6

typedef struct {
    int width, height;
    sl_image diffuse;     /* RGB, row 0 = top */
    sl_image specular[2]; /* indexed by sl_gt_geometry: [SL_GT_G_INV_LH2], [SL_GT_G_ONE] */
    sl_image mask;        /* 1 channel, 1 where covered, row 0 = top */
    long covered;
    uint64_t key;         /* hash of every input (what the cache is keyed on) */
    bool from_cache;
    double seconds;       /* integration time (0 when read from the cache) */
    long rays;            /* visibility: rays traced (eye rays for Ng included; 0 from the cache) */
    long ng_fallbacks;    /* visibility: covered pixels whose eye ray hit nothing, so the shading
                             normal stood in for the geometric one */
} sl_gt_image;

/* Read the cache when it matches, else integrate (and write the cache when a path is given).
 * False (and err) on a missing env or G-buffer, a covered texel with a non-finite field, a
 * negative or non-finite intensity or rotation, no memory, or a cache that cannot be written.
 * A cache file that is unreadable, stale or malformed is not an error: it is recomputed. */
bool sl_gt_image_compute(sl_gt_image *out, const sl_gt_image_desc *desc, sl_error *err);
void sl_gt_image_free(sl_gt_image *img);

/* The cache key of a request (no integration). */
uint64_t sl_gt_image_key(const sl_gt_image_desc *desc);

/* diffuse + specular[g] into `total` (allocated here; RGB, row 0 = top). */
bool sl_gt_image_total(const sl_gt_image *img, sl_gt_geometry g, sl_image *total, sl_error *err);

#endif
