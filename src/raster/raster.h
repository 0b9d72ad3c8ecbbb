/* raster.h - the rasterization pipeline: C vertex and fragment shaders, clipping,
 * fixed-point setup, tile binning and the parallel tile rasterizer.
 *
 * Consumes: a triangle mesh (sl_mesh: positions, normals, texcoords, indices), a
 *           program (vertex + fragment shader) with uniforms, and a render target.
 * Produces: texels of the target, written by the fragment shader, in GL window
 *           coordinates (row 0 = bottom, pixel centres at x+0.5, y+0.5).
 *
 * One draw call runs: vertex shader over every vertex -> homogeneous clipping
 * (near, far; guard-band planes only for triangles that leave the guard band) ->
 * triangle setup (8 sub-pixel bits, top-left rule, optional back-face culling,
 * degenerate and non-finite triangles dropped) -> binning into tiles -> per tile,
 * in parallel: clear (when asked), coverage tile -> 8x8 block -> row span -> pixel,
 * early depth test (LESS), then the fragment shader with perspective-correct
 * varyings, once per row span (fragment_span) or per fragment. A program that takes
 * derivatives (sl_program.derivatives) runs in aligned 2x2 quads instead, with helper
 * invocations for the quad's uncovered or occluded pixels; one that may discard
 * (sl_program.discards) writes depth and texel after the shader, only if it did not
 * discard. Programs with neither flag take the span and per-pixel paths unchanged.
 * A draw list bins several draws together and draws each tile once for all of them.
 * Primitive order within a tile is kept, so the result is bitwise identical for any
 * thread count and tile size, and the span path's to the per-pixel path's
 * (sl_raster_desc.plain), quads included. The shader API, the fragment built-ins
 * (shader.h: dFdx, dFdy, fwidth, discard) and how derivatives of any value a C
 * shader computes are found are described in docs/shader-api.md.
 *
 * Depth lives in the target's texels at `depth_offset` (the G-buffer texel's depth
 * field); while a tile is rasterized it is copied into a tile-local plane.
 *
 * Does not: blend, multisample, stencil, scissor, draw lines or points, or
 * clip against user planes. Fragment shaders cannot move depth. */
#ifndef SL_RASTER_H
#define SL_RASTER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/error.h"
#include "../core/glsl.h"
#include "../core/options.h" /* SL_RASTER_MAX_SIZE, SL_TILE_DEFAULT/MIN/MAX */
#include "../scene/scene.h"
#include "gbuffer.h"

#define SL_MAX_VARYINGS 16         /* floats a vertex shader may pass to the fragment shader */
#define SL_NO_DEPTH (-1L)          /* sl_target.depth_offset: depth test off */

/* Object-space attributes of one vertex, as the mesh stores them. */
typedef struct {
    vec3 position;
    vec3 normal;   /* (0,0,0) when the mesh has none */
    vec2 texcoord; /* (0,0) when the mesh has none */
    vec4 tangent;  /* xyz + handedness w (glTF TANGENT); (0,0,0,0) when the mesh has none */
    int index;     /* gl_VertexID: the vertex's index in the mesh */
} sl_vertex_in;

/* The 2x2 quad a fragment runs in (quad.c; opaque: shaders reach it through the
 * built-ins of shader.h). */
typedef struct sl_quad sl_quad;

/* What a fragment shader sees (GLSL built-ins plus the interpolated varyings). */
typedef struct {
    const float *varyings; /* varying_count floats, perspective-correct */
    vec4 frag_coord;       /* gl_FragCoord: x+0.5, y+0.5, window depth in [0,1], 1/w_clip */
    bool front_facing;     /* gl_FrontFacing: counter-clockwise in window coordinates */
    int x, y;              /* the pixel, row 0 = bottom */
    /* Only for programs with `derivatives` or `discards` (NULL and 0 otherwise: then
     * the derivative built-ins return 0 and discard() does nothing). */
    sl_quad *quad;         /* the quad's derivative records and discard marks */
    int lane;              /* 0..3: (x & 1) + 2 * (y & 1) */
    bool helper;           /* gl_HelperInvocation: uncovered or occluded, writes nothing */
} sl_fragment_in;

/* What a span fragment shader sees: the n fragments of one triangle in one row that
 * passed the depth test, left to right, in structure-of-arrays form (element j of
 * every array belongs to fragment j). Each value is bitwise the one the per-pixel
 * shader would get in sl_fragment_in; frag_coord.xy is (x[j] + 0.5, y + 0.5). */
#define SL_SPAN_MAX 256 /* = SL_TILE_MAX: a span never leaves its tile's row */
typedef struct {
    int n;                                  /* 1 .. SL_SPAN_MAX */
    int y;                                  /* the row, row 0 = bottom */
    const int32_t *x;                       /* the columns, increasing */
    const float *varyings[SL_MAX_VARYINGS]; /* varyings[i][j]: varying i of fragment j */
    const float *frag_z;                    /* gl_FragCoord.z: window depth in [0,1] */
    const float *frag_w;                    /* gl_FragCoord.w: 1/w_clip */
    bool front_facing;
    char *row;                              /* texels of row y: fragment j's is row + x[j] * texel_size */
    size_t texel_size;
} sl_fragment_span;

/* Vertex shader: object-space attributes -> clip-space position and varyings. */
typedef void (*sl_vertex_shader)(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings);
/* Fragment shader: writes the whole texel (the depth test has already passed). */
typedef void (*sl_fragment_shader)(const void *uniforms, const sl_fragment_in *in, void *texel);
/* Optional span form of the same fragment shader: must leave every texel exactly as
 * `fragment` called on each fragment of the span would (tested for the built-in pair). */
typedef void (*sl_fragment_span_shader)(const void *uniforms, const sl_fragment_span *span);

/* Optional quad form of a derivative-taking fragment shader: one call for the four
 * lanes of a 2x2 quad (in[lane], lane = (x & 1) + 2 * (y & 1); helpers have
 * in[l].helper set), each writing its own scratch texel[lane] (which starts as the
 * target's texel), marking discards with discard(&in[l]). It takes its derivatives
 * as differences between its lanes (shader.h: sl_quad_dfdx...), and must leave every
 * scratch texel and discard mark exactly as `fragment` run through the generic rounds
 * does (docs/shader-api.md "Quads"); the plain path (sl_raster_desc.plain) always runs
 * the rounds, so test_raster_span-style comparisons check it. */
typedef void (*sl_fragment_quad_shader)(const void *uniforms, const sl_fragment_in in[4], void *const texel[4]);

/* What a multi-quad shader sees (sl_program.fragment_quads): n quads of one triangle, in
 * structure-of-arrays form over their lanes. Lane l of quad q is element 4 q + l of every
 * per-lane array: pixel (qx[q] + (l & 1), qy[q] + (l >> 1)). Each lane's values are bitwise
 * what fragment_quad's in[l] holds for that quad (helpers included, extrapolated). The shader
 * writes texel[4 q + l] (scratch or the target's texel, as for fragment_quad) and sets
 * discarded[4 q + l] to 1 for a lane it discards (all 0 on entry). */
#define SL_QUADS_MAX 16                   /* quads a call: an 8x8 block's */
#define SL_QUAD_LANES (4 * SL_QUADS_MAX) /* lanes a call: 64 */
typedef struct {
    int n;                                  /* quads, 1 .. SL_QUADS_MAX */
    const int32_t *qx, *qy;                 /* per quad: its lane 0's pixel (both even) */
    const float *varyings[SL_MAX_VARYINGS]; /* varyings[i][4 q + l] */
    const float *frag_z;                    /* per lane: gl_FragCoord.z */
    const float *frag_w;                    /* per lane: gl_FragCoord.w */
    const uint8_t *helper;                  /* per lane: 1 for a helper invocation */
    bool front_facing;
    void *const *texel;                     /* per lane: where the lane's texel goes */
    uint8_t *discarded;                     /* per lane: set to 1 by the shader to discard */
} sl_fragment_quads;

/* Optional multi-quad form: one call for up to SL_QUADS_MAX quads (sl_fragment_quads), so a
 * shader's per-lane and per-quad work (coordinates, levels of detail, fetches, normals) runs
 * in vector loops over 64 lanes instead of 4. Same rule as fragment_quad: every texel and
 * discard mark exactly as `fragment` run through the generic rounds leaves them. Used on the
 * span path instead of fragment_quad when both are set. */
typedef void (*sl_fragment_quads_shader)(const void *uniforms, const sl_fragment_quads *q);

typedef struct {
    sl_vertex_shader vertex;
    sl_fragment_shader fragment;
    int varying_count;                     /* 0 .. SL_MAX_VARYINGS */
    sl_fragment_span_shader fragment_span; /* NULL: the pipeline calls `fragment` per fragment; unused
                                              by programs with `derivatives` or `discards` */
    bool derivatives;                      /* the fragment shader takes derivatives (or samples with an
                                              implicit level): it runs in 2x2 quads with helpers */
    bool discards;                         /* the fragment shader may discard: depth is written after it */
    sl_fragment_quad_shader fragment_quad; /* NULL: the generic rounds (`derivatives` programs only) */
    bool quad_writes_texel;                /* fragment_quad writes every byte of the texel of each lane
                                              that does not discard, and reads none: its texels then do
                                              not start as the target's (not copied in), and a live lane
                                              of a program that cannot discard writes the target's in
                                              place (tile.c quad()) */
    sl_fragment_quads_shader fragment_quads; /* NULL: fragment_quad per quad (or the rounds); needs
                                                `derivatives`; quad_writes_texel applies to it too */
    bool stores;                           /* the fragment shader stores outside its texel (GLSL's image
                                              stores: through its uniforms), only where
                                              sl_fragment_stores(in) (shader.h): the generic rounds
                                              then run once more, with stores on, after their fixed
                                              point. A shader that cannot discard and stores only at
                                              its own pixel may leave it off: its last round
                                              overwrites what the earlier rounds stored */
    bool writes_depth;                     /* every form of the fragment shader writes frag_coord.z
                                              (frag_z) into the target's depth field (its texel's float
                                              at sl_target.depth_offset) of each texel it writes: the
                                              tile plane's depth, so a list of such programs leaves
                                              the plane in its texels already and the tile does not
                                              copy it back (tile.c) */
} sl_program;

/* A render target: width * height texels of texel_size bytes, row 0 = bottom. */
typedef struct {
    int width, height;
    size_t texel_size;
    void *texels;
    long depth_offset; /* byte offset of a float depth in each texel, or SL_NO_DEPTH */
    /* Optional (NULL: none): per-tile hooks for data that programs write beside the texels (an
     * image store, such as the G-buffer's extra plane, gbuffer.h), run by the thread that draws
     * the tile while the tile is hot in cache. Pixels x0..x1, y0..y1 (inclusive, row 0 = bottom).
     * tile_clear: the tile is being cleared (sl_draw.clear), before anything is drawn into it.
     * tile_drawn: after a tile pass drew triangles into the tile (once per RAST_BATCH triangles of
     * a list, so it must be idempotent), with the tile's depths as its texels now hold them:
     * depth[(y - y0) * stride + (x - x0)] (NULL without a depth test). */
    void (*tile_clear)(void *ctx, int x0, int y0, int x1, int y1);
    void (*tile_drawn)(void *ctx, int x0, int y0, int x1, int y1, const float *depth, int stride);
    void *tile_ctx;
} sl_target;

typedef enum {
    SL_CULL_NONE, /* draw both faces (GL with GL_CULL_FACE disabled) */
    SL_CULL_BACK, /* drop clockwise triangles (GL_CCW front face, GL_BACK culled) */
} sl_cull_mode;

typedef struct {
    const sl_program *program;
    const void *vs_uniforms;
    const void *fs_uniforms;
    const sl_mesh *mesh;
    sl_cull_mode cull;
    /* Not NULL: texel_size bytes every texel of the target is set to before this draw
     * (as glClear before it), by the tile stage, each tile just before it is drawn,
     * on the thread that draws it (while the tile is in cache). */
    const void *clear;
} sl_draw;

/* Counters for one or more draws; only gathered when sl_raster_desc.stats is set. */
typedef struct {
    long long triangles_in;      /* index triples submitted */
    long long triangles_clipped; /* that needed clipping (near, far or guard band) */
    long long triangles_culled;  /* back faces dropped */
    long long triangles_dropped; /* degenerate, non-finite, outside the view or covering no pixel centre */
    long long triangles_binned;  /* setup records that reached at least one tile (after clipping) */
    long long bin_entries;       /* (triangle, tile) pairs */
    long long tiles_full;        /* bin entries whose triangle covers the whole tile */
    long long blocks_full;       /* 8x8 blocks filled without per-pixel edge tests */
    long long fragments_tested;  /* covered pixels reaching the depth test */
    long long fragments_shaded;  /* fragments that passed the depth test and ran the shader (not helpers;
                                    a quad's lane counts once however many rounds it ran) */
    long long fragments_discarded; /* of those, discarded: nothing written */
    long long fragments_late_z;  /* depth written after the shader (programs that may discard) */
    long long quads;             /* 2x2 quads shaded (derivative-taking programs) */
    long long quad_rounds;       /* rounds those quads ran (each round calls the shader on 4 lanes;
                                    the quad form counts 1) */
    long long helper_invocations; /* helper lanes of those quads (once per quad, as GL runs them) */
    long long parallel_regions;  /* OpenMP parallel regions opened (a fork and a barrier each): a
                                    handful per draw list, whatever its number of draws */
} sl_raster_stats;

typedef struct {
    int threads;   /* 0 = omp_get_max_threads() (all cores unless OMP_NUM_THREADS says otherwise) */
    int tile_size; /* power of two in [SL_TILE_MIN, SL_TILE_MAX]; 0 = SL_TILE_DEFAULT */
    bool stats;    /* gather sl_raster_stats */
    bool plain;    /* debug: the per-pixel path only (per-fragment shader calls, no spans), to compare */
} sl_raster_desc;

typedef struct sl_raster sl_raster;

sl_raster *sl_raster_create(const sl_raster_desc *desc, sl_error *err);
void sl_raster_destroy(sl_raster *r);
int sl_raster_threads(const sl_raster *r);
int sl_raster_tile_size(const sl_raster *r);

/* Draw one mesh into the target. False (and err) only for invalid arguments
 * (bad sizes, indices out of range, too many varyings) or no memory; bad
 * geometry (NaN, degenerate, behind the eye) is dropped silently and counted. */
bool sl_raster_draw(sl_raster *r, const sl_target *target, const sl_draw *draw, sl_error *err);
/* Draw `count` draws into one target, with the result of drawing them one by one in
 * order, but binned together: one tile pass for the list (per RAST_BATCH triangles)
 * instead of one per draw, so each tile's depth and texels go through the cache once. */
bool sl_raster_draw_list(sl_raster *r, const sl_target *target, const sl_draw *draws, int count, sl_error *err);

/* Totals since creation or the last reset (all zero when stats are off). */
sl_raster_stats sl_raster_get_stats(const sl_raster *r);
void sl_raster_reset_stats(sl_raster *r);

/* ---- the built-in G-buffer program (gbuffer_shader.c; GLSL twin: shaders/gbuffer.vert/.frag) ---- */
typedef struct {
    mat4 uModel;
    mat4 uViewProj;
    mat3 uNormalMatrix; /* transpose(inverse(mat3(uModel))) */
    vec3 uKd, uKs;
    float uAlpha;
} sl_gbuffer_uniforms;

/* Varyings of the built-in pair: vWorldPos (3 floats), then vNormal (3 floats). */
#define SL_GBUFFER_VARYINGS 6
void sl_gbuffer_vert(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings);
void sl_gbuffer_frag(const void *uniforms, const sl_fragment_in *in, void *texel);
void sl_gbuffer_frag_span(const void *uniforms, const sl_fragment_span *span);
extern const sl_program sl_gbuffer_program;

/* Fill the uniforms from a model matrix, view-projection and material. */
void sl_gbuffer_uniforms_init(sl_gbuffer_uniforms *u, mat4 model, mat4 view_proj, const sl_material *m);
/* The G-buffer as a render target (depth in the texel's depth field). With the extra plane, its
 * tile hooks clear the plane with the texels and resolve it after each tile pass (gbuffer.c). */
sl_target sl_gbuffer_target(sl_gbuffer *gb);

/* Clear the G-buffer and draw every object of the scene with the built-in pair,
 * both faces (no culling, as GL's default). The G-buffer must already be sized.
 * The clear is fused into the first object's draw (sl_draw.clear). */
bool sl_raster_scene(sl_raster *r, const sl_scene *scene, const sl_camera *cam, sl_gbuffer *gb, sl_error *err);

#endif
