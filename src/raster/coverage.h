/* coverage.h - where a masked material lets light through, for the passes that draw or trace the
 * scene without its G-buffer program: the depth-only programs of the shadow and sky visibility
 * maps (src/shadow) and the ground truth's tracer (src/shading/visibility.c). So that a leaf cut
 * out of its quad casts the leaf's shadow, not the quad's.
 *
 * The coverage is what the textured G-buffer program compares with alpha_cutoff
 * (gbuffer_textured.c): mask_map's r, else kd_map's a, at the map's own transformed coordinate
 * uv * uv_scale + uv_offset, with the map's sampler; a point is kept where the coverage is not
 * below the cutoff (GLSL: discard where coverage < cutoff). Read at level 0: a depth pass has no
 * screen to take derivatives from, so the level is the magnified one (GL's twin, shadow_depth.frag,
 * reads textureLod(.., 0.0), the same filter). A material that is not masked, or names neither
 * map, covers everywhere, as its G-buffer program keeps every fragment. */
#ifndef SL_RASTER_COVERAGE_H
#define SL_RASTER_COVERAGE_H

#include <stdbool.h>
#include <stdint.h>

#include "gbuffer_textured.h"
#include "scene/scene.h"

/* A masked material's coverage lookup. */
typedef struct {
    sl_sampler2D map; /* mask_map, else kd_map */
    int image;        /* its index in the scene's images (sl_scene_textures, GL's names) */
    vec4 st;          /* the map's coordinate: uv * st.xy + st.zw */
    int channel;      /* 0: mask_map's r; 3: kd_map's a */
    float cutoff;
} sl_coverage;

/* Whether material m lets light through a mask (masked, with mask_map or kd_map loaded in tex):
 * then *c is its lookup. False for an opaque caster (c untouched); tex may be NULL (every caster
 * opaque). */
bool sl_coverage_of(const sl_material *m, const sl_scene_textures *tex, sl_coverage *c);

/* Whether the mask keeps the surface at texture coordinate uv (coverage >= cutoff). */
static inline bool sl_coverage_keeps(const sl_coverage *c, vec2 uv)
{
    vec2 p = vec2(uv.x * c->st.x + c->st.z, uv.y * c->st.y + c->st.w);
    vec4 t = sl_texture_sample(&c->map, p, 0.0f);
    float coverage = c->channel == 0 ? t.x : t.w;
    return !(coverage < c->cutoff);
}

/* FNV-1a 64 of what a coverage lookup reads, continuing h: the cutoff, the coordinate's
 * transform, the sampler state and the map's level 0 (a cache keyed on the scene changes with
 * the mask). */
uint64_t sl_coverage_hash(uint64_t h, const sl_coverage *c);

#endif
