/* rast_internal.h - what the pipeline files (raster.c, clip.c, setup.c, tile.c) share.
 *
 * Data flow of one draw list (one or more draws into one target): raster.c runs the
 * vertex shader of every draw into rast_vpos + varyings, then in batches of triangles
 * (of all draws, in order): setup.c (clipping via clip.c, fixed-point setup, binning)
 * fills one rast_chunk per slice of the batch, in parallel; tile.c walks every tile's
 * bins, chunk by chunk in submission order, in parallel over tiles. Each set-up
 * triangle remembers its draw (rast_call), whose program shades it.
 *
 * Fixed-point bit budget (8 sub-pixel bits, docs/conventions.md "Fixed point in the rasterizer"):
 *   Window coordinates are kept inside the guard band |x|,|y| < RAST_GUARD_PX = 16000
 *   (< 2^14) by clipping; SL_RASTER_MAX_SIZE = 8192 lies inside it. Snapped to 1/256
 *   pixel: |X| < 2^22. Edge coefficients a = -dy, b = dx: |a|,|b| < 2^23 (int32).
 *   c = dy*Xa - dx*Ya: |c| < 2 * 2^23 * 2^22 = 2^46. An edge value at any pixel of
 *   the target, E = 256a*x + 256b*y + c', is below 3 * 2^46 < 2^48: int64 with 15
 *   bits to spare, and so is twice the area. int32 edge values would need |X| < 2^15,
 *   a 128-pixel guard band: not enough, hence int64 everywhere.
 *   The guard band is also where float stops being exact enough to snap: below
 *   2^14 a float window coordinate has an ulp of at most 2^-10 pixel, finer than
 *   the 2^-8 grid, so snapping with lrintf never loses a sub-pixel step.
 */
#ifndef SL_RAST_INTERNAL_H
#define SL_RAST_INTERNAL_H

#include <stdint.h>

#include "raster.h"

#define RAST_SUBPIXEL_BITS 8
#define RAST_SUBPIXEL_ONE (1 << RAST_SUBPIXEL_BITS)
#define RAST_GUARD_PX 16000.0f
_Static_assert(SL_RASTER_MAX_SIZE < (int)RAST_GUARD_PX, "the largest target must lie inside the guard band");
#define RAST_BLOCK 8                   /* coverage block inside a tile: 8x8 pixels */
#define RAST_SPAN_MIN_WIDTH 8         /* narrower triangles (and at most 8 rows) are small: tile.c */
#define RAST_BATCH 131072              /* triangles set up and binned before the tiles are drawn */
#define RAST_CACHE_LINE 64
#define RAST_W_EPSILON 1e-6f           /* clip plane w >= eps: keeps the divide finite for any projection */
#define RAST_CLIP_MAX 16               /* 3 vertices + one per clip plane, rounded up */
#define RAST_BIN_FULL 0x80000000u      /* bin item flag: the triangle covers the whole tile */
#define RAST_MAX_CALLS 65536           /* draws binned together (rast_tri.call is 16 bits: keeps it 128 bytes) */
/* Less work than this in a stage of a draw list, counted in vertices shaded, and the stage runs
 * on the calling thread: a parallel region costs a fork and a barrier, microseconds on an idle
 * machine and up to milliseconds on a loaded one (a woken thread waits for a core), more than
 * shading a few thousand vertices. Work is split into the same slices either way. The other
 * stages' items in vertices' worth (1 thread, pbr.json at 1280x720: an index checked about 1 ns,
 * a vertex shaded 25, a triangle set up and binned 90): RAST_WORK_INDICES indices are one vertex,
 * a triangle is RAST_WORK_TRIANGLE. So pbr.json's 3982 triangles are set up on both threads (0.35
 * ms alone), and its 11946 indices checked on one (12 us, less than the region). */
#define RAST_PARALLEL_MIN 4096
#define RAST_WORK_INDICES 16
#define RAST_WORK_TRIANGLE 4

/* Clip planes (bit = vertex outside). RAST_BAD marks a non-finite vertex. */
enum {
    RAST_PLANE_NEAR = 1u << 0,   /* z >= -w */
    RAST_PLANE_FAR = 1u << 1,    /* z <=  w */
    RAST_PLANE_W = 1u << 2,      /* w >= eps */
    RAST_PLANE_LEFT = 1u << 3,   /* x >= -gx w  (guard band) */
    RAST_PLANE_RIGHT = 1u << 4,  /* x <=  gx w */
    RAST_PLANE_BOTTOM = 1u << 5, /* y >= -gy w */
    RAST_PLANE_TOP = 1u << 6,    /* y <=  gy w */
    RAST_PLANE_COUNT = 7,
    RAST_BAD = 1u << 7,
};

/* A window position, exact (rast_window_exact below): x, y in pixels, window depth, 1/w. */
typedef struct {
    double x, y, z, iw;
} rast_exact;

/* The vertex stage's output position: clip coordinates, and (when the vertex is
 * inside every plane) its snapped window position and its exact one, made once per
 * vertex rather than in the setup of each triangle that shares it. */
typedef struct {
    vec4 clip;
    int32_t X, Y;   /* window position in 1/256 pixel */
    unsigned outcode;
    rast_exact win; /* rast_window_exact(clip), when outcode is 0 */
} rast_vpos;

/* A vertex during clipping: clip position and varyings. */
typedef struct {
    vec4 clip;
    float v[SL_MAX_VARYINGS];
} rast_cvert;

/* A vertex entering triangle setup: its snapped position for the edges, its exact one
 * for the attribute planes (setup.c). */
typedef struct {
    int32_t X, Y;
    rast_exact win;
    const float *v; /* varying_count varyings, not yet divided by w */
    vec4 clip;      /* the clip position, for the facet plane (sl_target.facets) */
} rast_wvert;

/* A set-up triangle, counter-clockwise. Edge k: E_k(x, y) = ex[k]*x + ey[k]*y + ec[k]
 * for the centre of pixel (x, y), biased by the fill rule so covered <=> all E_k >= 0.
 * Attributes are planes f(x, y) = f0 + fdx*(x - xmin) + fdy*(y - ymin) over pixel indices,
 * from the first pixel of the bounds (integers below 2^13: x - xmin is exact in float), f0 the
 * value at its centre. 128 bytes, two cache lines (the chunk's array is aligned to them). */
typedef struct {
    int64_t ex[3], ey[3], ec[3];
    int32_t xmin, ymin, xmax, ymax; /* pixel bounds, inside the target; (xmin, ymin) is the planes' origin */
    float z[3];                     /* z0, dz/dx, dz/dy */
    float iw[3];                    /* 1/w plane */
    float iw_lo, iw_hi;             /* range of 1/w over the vertices: a covered pixel's stays inside
                                       (helpers extrapolate: tile.c quad()) */
    uint32_t vary;                  /* offset of varying_count planes (3 floats each, of v/w) in the chunk pool,
                                       then, for a target with facets, the facet normal (3 floats) */
    uint16_t call;                  /* index of its draw in rast_draw.calls (< RAST_MAX_CALLS) */
    bool front;
} rast_tri;
_Static_assert(sizeof(rast_tri) == 2 * RAST_CACHE_LINE, "a set-up triangle is two cache lines");

typedef struct {
    uint32_t *items; /* triangle index in the chunk, | RAST_BIN_FULL */
    int count, cap;
} rast_bin;

/* The setup output of one contiguous slice of a batch. Chunks (and tasks) are written
 * by different threads side by side: each is aligned to its own cache lines. */
typedef struct {
    _Alignas(RAST_CACHE_LINE) int tri_count;
    int tri_cap;
    rast_tri *tris;
    float *vary;
    size_t vary_count, vary_cap;
    rast_bin *bins; /* one per tile */
    int bin_count;
    sl_raster_stats stats;
    bool oom;
} rast_chunk;

/* One row span of the tile stage (tile.c), structure of arrays: the columns that pass,
 * their depth, 1/w, w and varyings, as the span fragment shader reads them; and the
 * coverage and depth-test flags of the row before packing. A small triangle packs the
 * passing pixels of all its rows (at most RAST_BLOCK x RAST_BLOCK) into one set, row
 * after row, with each pixel's row offset in fy. */
typedef struct {
    _Alignas(RAST_CACHE_LINE) float vary[SL_MAX_VARYINGS][SL_SPAN_MAX];
    _Alignas(RAST_CACHE_LINE) float z[SL_SPAN_MAX];
    _Alignas(RAST_CACHE_LINE) float iw[SL_SPAN_MAX];
    _Alignas(RAST_CACHE_LINE) float w[SL_SPAN_MAX];
    _Alignas(RAST_CACHE_LINE) int32_t x[SL_SPAN_MAX];
    _Alignas(RAST_CACHE_LINE) int32_t flags[SL_SPAN_MAX];
    _Alignas(RAST_CACHE_LINE) float fy[SL_SPAN_MAX]; /* small triangles: each fragment's row offset (tile.c) */
} rast_span;

/* The quads the tile stage gathers for a multi-quad shader (sl_program.fragment_quads; tile.c
 * quads_flush), structure of arrays over lanes (lane l of quad q at 4 q + l): what the depth
 * test left of each quad (its offsets from the triangle's origin, depth, live lanes), then the
 * inputs made for all lanes at once, and what the shader gets. */
typedef struct {
    _Alignas(RAST_CACHE_LINE) float vary[SL_MAX_VARYINGS][SL_QUAD_LANES];
    _Alignas(RAST_CACHE_LINE) float fx[SL_QUAD_LANES];
    _Alignas(RAST_CACHE_LINE) float fy[SL_QUAD_LANES];
    _Alignas(RAST_CACHE_LINE) float z[SL_QUAD_LANES];
    _Alignas(RAST_CACHE_LINE) float iw[SL_QUAD_LANES];
    _Alignas(RAST_CACHE_LINE) float w[SL_QUAD_LANES];
    _Alignas(RAST_CACHE_LINE) void *texel[SL_QUAD_LANES]; /* what the shader writes */
    char *target[SL_QUAD_LANES];                           /* the lane's texel, NULL outside */
    uint8_t helper[SL_QUAD_LANES];
    uint8_t discarded[SL_QUAD_LANES];
    int32_t qx[SL_QUADS_MAX], qy[SL_QUADS_MAX];
    int n;                       /* quads gathered */
    sl_fragment_quads in;        /* the shader's view (arrays point into this) */
} rast_quads;

/* The 2x2 quad of a derivative-taking program (quad.c runs its rounds; glsl.h's
 * built-ins write it). Lane l is pixel (qx + (l & 1), qy + (l >> 1)). In a round every
 * lane runs the whole shader; its k-th derivative call records its argument in
 * rec[cur][lane][k] and returns the difference of the round before's records of call k
 * (rec[cur ^ 1]). A round that records exactly what the round before recorded is a
 * fixed point: the quad is done (docs/shader-api.md "Quads"). The bound on calls keeps
 * the records in the task (8 KiB): calls past it are recorded nowhere and return 0. */
#define RAST_QUAD_CALLS 64
struct sl_quad {
    float rec[2][4][RAST_QUAD_CALLS][4]; /* [round parity][lane][call][component], unused components 0 */
    int count[2][4];                     /* calls recorded per round parity and lane */
    int cur;                             /* parity of the running round */
    bool derivs;                         /* false: a discard-only program, derivatives return 0 */
    bool discarded[4];                   /* discard() in this round */
    bool rehearsal;                      /* stores outside the texel do not count in this round
                                            (sl_fragment_stores): a round before the fixed point of
                                            a program with `stores` */
};

/* Per-thread scratch for the tile stage, and each slice's answer of the index check. */
typedef struct {
    _Alignas(RAST_CACHE_LINE) float *depth; /* tile_size * tile_size, and RAST_SPAN_MIN_WIDTH of padding */
    rast_span *span;                        /* NULL for a plain context */
    sl_quad *quad;                          /* quads and discards */
    rast_quads *quads;                      /* multi-quad shaders; NULL for a plain context */
    char *scratch;                          /* 4 texels: what a quad's lanes (or a discarding fragment) write */
    size_t scratch_cap;                     /* bytes */
    sl_raster_stats stats;
    int bad_call;       /* index check: the first draw of the slice with a bad index, or -1 */
    long long bad_at;   /* and the last bad index position in that draw (within the slice) */
} rast_task;

/* One draw of a list: its program, uniforms and mesh, and where its vertex stage
 * output lives. Its triangles are [first_tri, first_tri + triangle_count) of the list. */
typedef struct {
    const sl_program *program;
    const void *vs_uniforms, *fs_uniforms;
    const sl_mesh *mesh;
    sl_cull_mode cull;
    int nvary;
    long long first_tri;
    size_t first_vertex;   /* of the list's vertices: vpos = sl_raster.vpos + first_vertex */
    const rast_vpos *vpos; /* vertex_count */
    const float *vvary;    /* vertex_count * nvary */
} rast_call;

/* Everything one draw list needs, read-only inside the parallel regions. */
typedef struct {
    const sl_target *target;
    const rast_call *calls;
    int call_count;
    long long tri_count; /* all draws */
    float gx, gy;        /* guard band in NDC */
    int tile_size, tile_shift, tiles_x, tiles_y;
    bool stats;
    bool spans;          /* the span path (tile.c); false: per pixel */
    bool depth_written;  /* every program of the list writes_depth: no copy of the tile's depth back */
    /* sl_draw.clear, during the first batch only: the clear texel repeated over a tile
     * row (tile_size texels), and its depth */
    const char *clear_row;
    float clear_depth;
} rast_draw;

struct sl_raster {
    int threads;
    int tile_size, tile_shift;
    bool stats_on;
    sl_raster_stats stats;
    rast_vpos *vpos;
    float *vvary;
    size_t vertex_cap, vvary_cap; /* vertices, floats */
    rast_call *calls;
    int call_cap;
    rast_chunk *chunks;
    int chunk_count;
    rast_task *tasks; /* one per thread */
    bool plain;
    bool keep_extra;  /* the G-buffer keeps its extra plane with no material writing it (sl_raster_keep_extra) */
    char *clear_row;  /* tile_size texels of the clear value */
    size_t clear_row_cap;
};

/* clip.c */
unsigned sl_rast_outcode(vec4 c, float gx, float gy);
/* Clip triangle `in` against the planes in `planes`; returns the polygon's vertex count (0 or 3..). */
int sl_rast_clip_triangle(const rast_cvert in[3], unsigned planes, int nvary, float gx, float gy,
                       rast_cvert out[RAST_CLIP_MAX]);

/* Clip -> window, snapped: the one place the snapping viewport transform is written, so a
 * vertex shared by two triangles lands on the same fixed-point position whichever path
 * computed it. The edges (coverage) use this position. */
static inline void rast_to_window(const sl_target *tg, vec4 c, int32_t *X, int32_t *Y)
{
    float inv = 1.0f / c.w;
    float xw = (c.x * inv * 0.5f + 0.5f) * (float)tg->width;
    float yw = (c.y * inv * 0.5f + 0.5f) * (float)tg->height;
    *X = (int32_t)lrintf(xw * (float)RAST_SUBPIXEL_ONE);
    *Y = (int32_t)lrintf(yw * (float)RAST_SUBPIXEL_ONE);
}

/* Clip -> window, exact: the same transform in double, not snapped, with window depth
 * z_ndc*0.5+0.5 and 1/w. The attribute planes (depth, 1/w, v/w) are built on it, as llvmpipe
 * builds them on its float positions: on the snapped ones a varying is off by its gradient
 * times up to 1/512 pixel, and near a horizon that is a large share of its value (setup.c). */
static inline rast_exact rast_window_exact(const sl_target *tg, vec4 c)
{
    double iw = 1.0 / (double)c.w;
    return (rast_exact){((double)c.x * iw * 0.5 + 0.5) * (double)tg->width,
                        ((double)c.y * iw * 0.5 + 0.5) * (double)tg->height, (double)c.z * iw * 0.5 + 0.5, iw};
}

/* setup.c: set up and bin triangles [first, last) of the draw list into `chunk`. */
void sl_rast_setup_range(const rast_draw *d, rast_chunk *chunk, long long first, long long last);

/* tile.c: draw every bin of tile `tile` from the chunks, in order (and clear it first
 * when d->clear_row is set: then every tile is visited, binned or not). */
void sl_rast_tile(const rast_draw *d, const rast_chunk *chunks, int chunk_count, int tile, rast_task *task);

/* quad.c: the rounds of the generic quad path. */
/* Start a quad: no records from a round before. `rounds`: the quad runs the generic rounds
 * (derivatives from the records); `stores`: its program stores outside the texel (sl_program). */
void sl_rast_quad_begin(sl_quad *q, bool rounds, bool stores);
/* Start a round: flip the parity, clear this round's records and discard marks. */
void sl_rast_quad_round(sl_quad *q);
/* After round number `rounds` (1, 2, ...): is the quad done? Yes at the fixed point (this
 * round recorded exactly what the round before recorded), or past the bound the proof gives;
 * a program with stores then runs one more round, the same bits again, with its stores on. */
bool sl_rast_quad_done(sl_quad *q, int rounds);

/* raster.c */
void sl_rast_stats_add(sl_raster_stats *to, const sl_raster_stats *from);

#endif
