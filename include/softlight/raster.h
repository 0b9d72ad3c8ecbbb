/* softlight/raster.h - draws: a program (program.h) over a mesh (scene.h) into a render target.
 *
 * A target is any array of fixed-size texels, row 0 = bottom (GL window coordinates, pixel
 * centres at x + 0.5, y + 0.5), with an optional float depth in each texel (depth test LESS).
 * One draw runs the vertex shader over every vertex, clips, sets the triangles up (8 sub-pixel
 * bits, top-left rule, optional back-face culling), bins them into tiles and shades the tiles in
 * parallel. Primitive order within a tile is kept, so the result is bitwise identical for any
 * thread count and tile size.
 *
 * Does not: blend, multisample, stencil, scissor, draw lines or points, or clip against user
 * planes. Fragment shaders cannot move depth. */
#ifndef SOFTLIGHT_RASTER_H
#define SOFTLIGHT_RASTER_H

#include <stdbool.h>
#include <stddef.h>

#include <softlight/program.h>
#include <softlight/scene.h>
#include <softlight/types.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SL_NO_DEPTH (-1L) /* sl_target.depth_offset: depth test off */

/* A render target: width * height texels of texel_size bytes, row 0 = bottom. */
typedef struct sl_target {
    int width, height;
    size_t texel_size;
    void *texels;
    long depth_offset; /* byte offset of a float depth in each texel, or SL_NO_DEPTH */
    /* Optional (NULL: none): per-tile hooks for data that programs write beside the texels (an
     * image store, such as the G-buffer's extra plane), run by the thread that draws the tile
     * while the tile is hot in cache. Pixels x0..x1, y0..y1 (inclusive, row 0 = bottom).
     * tile_clear: the tile is being cleared (sl_draw.clear), before anything is drawn into it.
     * tile_drawn: after a tile pass drew triangles into the tile (possibly several times per
     * draw list, so it must be idempotent), with the tile's depths as its texels now hold them:
     * depth[(y - y0) * stride + (x - x0)] (NULL without a depth test). */
    void (*tile_clear)(void *ctx, int x0, int y0, int x1, int y1);
    void (*tile_drawn)(void *ctx, int x0, int y0, int x1, int y1, const float *depth, int stride);
    void *tile_ctx;
    /* Optional (NULL: none): width * height facet normals written beside the texels. Wherever a
     * fragment writes its texel, its facet is set to the unit normal of the triangle's plane in
     * the space that facet_view_proj carries to clip space (a camera's view-projection: world
     * space), on the viewer's side (the eye's for a perspective view_proj, the side an orthographic
     * one looks from); a
     * draw's clear sets it to 0. The plane is the triangle's own, not the interpolated normals':
     * what a ray tracer would intersect. */
    sl_vec3 *facets;
    sl_mat4 facet_view_proj;
} sl_target;

typedef enum sl_cull_mode {
    SL_CULL_NONE, /* draw both faces (GL with GL_CULL_FACE disabled) */
    SL_CULL_BACK, /* drop clockwise triangles (GL_CCW front face, GL_BACK culled) */
} sl_cull_mode;

typedef struct sl_draw {
    const sl_program *program;
    const void *vs_uniforms;
    const void *fs_uniforms;
    const sl_mesh *mesh;
    sl_cull_mode cull;
    /* Not NULL: texel_size bytes every texel of the target is set to before this draw (as
     * glClear before it), tile by tile, on the thread that draws the tile. */
    const void *clear;
} sl_draw;

/* Counters for one or more draws; only gathered when sl_raster_desc.stats is set. */
typedef struct sl_raster_stats {
    long long triangles_in;        /* index triples submitted */
    long long triangles_clipped;   /* that needed clipping (near, far or guard band) */
    long long triangles_culled;    /* back faces dropped */
    long long triangles_dropped;   /* degenerate, non-finite, outside the view or covering no pixel centre */
    long long triangles_binned;    /* setup records that reached at least one tile (after clipping) */
    long long bin_entries;         /* (triangle, tile) pairs */
    long long tiles_full;          /* bin entries whose triangle covers the whole tile */
    long long blocks_full;         /* 8x8 blocks filled without per-pixel edge tests */
    long long fragments_tested;    /* covered pixels reaching the depth test */
    long long fragments_shaded;    /* fragments that passed the depth test and ran the shader (not helpers) */
    long long fragments_discarded; /* of those, discarded: nothing written */
    long long fragments_late_z;    /* depth written after the shader (programs that may discard) */
    long long quads;               /* 2x2 quads shaded (derivative-taking programs) */
    long long quad_rounds;         /* rounds those quads ran */
    long long helper_invocations;  /* helper lanes of those quads */
    long long parallel_regions;    /* OpenMP parallel regions opened */
} sl_raster_stats;

typedef struct sl_raster_desc {
    int threads;   /* 0 = all cores (omp_get_max_threads()) */
    int tile_size; /* power of two in [16, 256]; 0 = the default, 64 */
    bool stats;    /* gather sl_raster_stats */
    bool plain;    /* debug: the per-pixel path only (per-fragment shader calls, no spans), to compare */
} sl_raster_desc;

typedef struct sl_raster sl_raster;

SL_API sl_raster *sl_raster_create(const sl_raster_desc *desc, sl_error *err);
SL_API void sl_raster_destroy(sl_raster *r);
SL_API int sl_raster_threads(const sl_raster *r);
SL_API int sl_raster_tile_size(const sl_raster *r);

/* Draw one mesh into the target. False (and err) only for invalid arguments (bad sizes, indices
 * out of range, too many varyings) or no memory; bad geometry (NaN, degenerate, behind the eye)
 * is dropped silently and counted. */
SL_API bool sl_raster_draw(sl_raster *r, const sl_target *target, const sl_draw *draw, sl_error *err);
/* Draw `count` draws into one target, with the result of drawing them one by one in order, but
 * binned together, so each tile's depth and texels go through the cache once. */
SL_API bool sl_raster_draw_list(sl_raster *r, const sl_target *target, const sl_draw *draws, int count,
                                sl_error *err);

/* Totals since creation or the last reset (all zero when stats are off). */
SL_API sl_raster_stats sl_raster_get_stats(const sl_raster *r);
SL_API void sl_raster_reset_stats(sl_raster *r);

#ifdef __cplusplus
}
#endif

#endif
