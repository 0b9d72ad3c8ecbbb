/* raster.c - the rasterizer context and the draw call that drives the stages.
 *
 * sl_raster_draw: validate, run the vertex shader over every vertex (parallel,
 * each vertex written once by one thread), then for each batch of RAST_BATCH
 * triangles: set up and bin one contiguous slice per thread into its own chunk
 * (setup.c), and rasterize the tiles in parallel (tile.c). Chunks are read back in
 * slice order, so bins hold triangles in submission order for any thread count.
 * Batching bounds the memory of set-up triangles (about 200 bytes each). */
#include "rast_internal.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

void rast_stats_add(sl_raster_stats *to, const sl_raster_stats *from)
{
    to->triangles_in += from->triangles_in;
    to->triangles_clipped += from->triangles_clipped;
    to->triangles_culled += from->triangles_culled;
    to->triangles_dropped += from->triangles_dropped;
    to->triangles_binned += from->triangles_binned;
    to->bin_entries += from->bin_entries;
    to->tiles_full += from->tiles_full;
    to->blocks_full += from->blocks_full;
    to->fragments_tested += from->fragments_tested;
    to->fragments_shaded += from->fragments_shaded;
}

sl_raster *sl_raster_create(const sl_raster_desc *desc, sl_error *err)
{
    sl_raster_desc dd = desc ? *desc : (sl_raster_desc){0};
    if (dd.threads < 0 || dd.threads > 1024) {
        sl_fail(err, SL_ERR_RANGE, "raster: thread count %d outside 0..1024", dd.threads);
        return NULL;
    }
    int ts = dd.tile_size ? dd.tile_size : SL_TILE_DEFAULT;
    if (ts < SL_TILE_MIN || ts > SL_TILE_MAX || (ts & (ts - 1))) {
        sl_fail(err, SL_ERR_RANGE, "raster: tile size %d is not a power of two in %d..%d", ts, SL_TILE_MIN,
                SL_TILE_MAX);
        return NULL;
    }
    sl_raster *r = calloc(1, sizeof *r);
    if (!r) {
        sl_fail(err, SL_ERR_MEMORY, "raster: out of memory");
        return NULL;
    }
    r->threads = dd.threads ? dd.threads : omp_get_max_threads();
    r->tile_size = ts;
    while ((1 << r->tile_shift) < ts)
        r->tile_shift++;
    r->stats_on = dd.stats;
    r->chunk_count = r->threads;
    r->chunks = aligned_alloc(RAST_CACHE_LINE, (size_t)r->chunk_count * sizeof *r->chunks);
    r->tasks = aligned_alloc(RAST_CACHE_LINE, (size_t)r->threads * sizeof *r->tasks);
    bool ok = r->chunks && r->tasks;
    if (r->chunks)
        memset(r->chunks, 0, (size_t)r->chunk_count * sizeof *r->chunks);
    if (r->tasks)
        memset(r->tasks, 0, (size_t)r->threads * sizeof *r->tasks);
    for (int i = 0; ok && i < r->threads; i++)
        ok = (r->tasks[i].depth = malloc((size_t)ts * (size_t)ts * sizeof(float))) != NULL;
    if (!ok) {
        sl_raster_destroy(r);
        sl_fail(err, SL_ERR_MEMORY, "raster: out of memory");
        return NULL;
    }
    return r;
}

void sl_raster_destroy(sl_raster *r)
{
    if (!r)
        return;
    for (int c = 0; r->chunks && c < r->chunk_count; c++) {
        rast_chunk *ch = &r->chunks[c];
        for (int i = 0; i < ch->bin_count; i++)
            free(ch->bins[i].items);
        free(ch->bins);
        free(ch->tris);
        free(ch->vary);
    }
    for (int i = 0; r->tasks && i < r->threads; i++)
        free(r->tasks[i].depth);
    free(r->chunks);
    free(r->tasks);
    free(r->vpos);
    free(r->vvary);
    free(r);
}

int sl_raster_threads(const sl_raster *r) { return r->threads; }
int sl_raster_tile_size(const sl_raster *r) { return r->tile_size; }
sl_raster_stats sl_raster_get_stats(const sl_raster *r) { return r->stats; }
void sl_raster_reset_stats(sl_raster *r) { memset(&r->stats, 0, sizeof r->stats); }

static bool validate(const sl_target *t, const sl_draw *d, sl_error *err)
{
    if (!t || !d || !d->program || !d->mesh)
        return sl_fail(err, SL_ERR_RANGE, "raster: draw without target, program or mesh");
    if (t->width < 1 || t->height < 1 || t->width > SL_RASTER_MAX_SIZE || t->height > SL_RASTER_MAX_SIZE)
        return sl_fail(err, SL_ERR_RANGE, "raster: target %dx%d outside 1..%d", t->width, t->height,
                       SL_RASTER_MAX_SIZE);
    if (!t->texels || t->texel_size == 0)
        return sl_fail(err, SL_ERR_RANGE, "raster: target without texels");
    if (t->depth_offset != SL_NO_DEPTH &&
        (t->depth_offset < 0 || (size_t)t->depth_offset + sizeof(float) > t->texel_size))
        return sl_fail(err, SL_ERR_RANGE, "raster: depth offset %ld outside a %zu-byte texel", t->depth_offset,
                       t->texel_size);
    const sl_program *p = d->program;
    if (!p->vertex || !p->fragment)
        return sl_fail(err, SL_ERR_RANGE, "raster: program without vertex or fragment shader");
    if (p->varying_count < 0 || p->varying_count > SL_MAX_VARYINGS)
        return sl_fail(err, SL_ERR_RANGE, "raster: %d varyings (at most %d)", p->varying_count, SL_MAX_VARYINGS);
    const sl_mesh *m = d->mesh;
    if (m->vertex_count < 0 || m->triangle_count < 0 || (m->triangle_count > 0 && (!m->indices || !m->positions)))
        return sl_fail(err, SL_ERR_RANGE, "raster: mesh without positions or indices");
    return true;
}

/* Make room for the vertex stage and for one bin per tile in every chunk. */
static bool reserve(sl_raster *r, const sl_mesh *m, int nvary, int tiles, sl_error *err)
{
    size_t nv = (size_t)m->vertex_count;
    if (nv > r->vertex_cap) {
        rast_vpos *vp = realloc(r->vpos, nv * sizeof *vp);
        if (!vp)
            return sl_fail(err, SL_ERR_MEMORY, "raster: out of memory for %zu vertices", nv);
        r->vpos = vp;
        r->vertex_cap = nv;
    }
    size_t nf = nv * (size_t)nvary;
    if (nf == 0)
        nf = 1; /* never NULL: setup offsets into it even with no varyings */
    if (nf > r->vvary_cap) {
        float *vv = realloc(r->vvary, nf * sizeof *vv);
        if (!vv)
            return sl_fail(err, SL_ERR_MEMORY, "raster: out of memory for %zu varyings", nf);
        r->vvary = vv;
        r->vvary_cap = nf;
    }
    for (int c = 0; c < r->chunk_count; c++) {
        rast_chunk *ch = &r->chunks[c];
        if (ch->bin_count >= tiles)
            continue;
        rast_bin *b = realloc(ch->bins, (size_t)tiles * sizeof *b);
        if (!b)
            return sl_fail(err, SL_ERR_MEMORY, "raster: out of memory for %d bins", tiles);
        memset(b + ch->bin_count, 0, (size_t)(tiles - ch->bin_count) * sizeof *b);
        ch->bins = b;
        ch->bin_count = tiles;
    }
    return true;
}

bool sl_raster_draw(sl_raster *r, const sl_target *target, const sl_draw *draw, sl_error *err)
{
    if (!validate(target, draw, err))
        return false;
    const sl_mesh *m = draw->mesh;
    const sl_program *prog = draw->program;
    int nvary = prog->varying_count;
    rast_draw d = {
        .target = target,
        .program = prog,
        .vs_uniforms = draw->vs_uniforms,
        .fs_uniforms = draw->fs_uniforms,
        .mesh = m,
        .cull = draw->cull,
        .nvary = nvary,
        .gx = 2.0f * RAST_GUARD_PX / (float)target->width - 1.0f,
        .gy = 2.0f * RAST_GUARD_PX / (float)target->height - 1.0f,
        .tile_size = r->tile_size,
        .tile_shift = r->tile_shift,
        .tiles_x = (target->width + r->tile_size - 1) >> r->tile_shift,
        .tiles_y = (target->height + r->tile_size - 1) >> r->tile_shift,
        .stats = r->stats_on,
    };
    int tiles = d.tiles_x * d.tiles_y;
    if (!reserve(r, m, nvary, tiles, err))
        return false;

    /* Indices are checked before any vertex is shaded: a bad one is an error, not a crash. */
    long long bad = -1;
    long long nidx = 3LL * m->triangle_count;
    uint32_t vc = (uint32_t)m->vertex_count;
#pragma omp parallel for schedule(static) num_threads(r->threads) reduction(max : bad)
    for (long long i = 0; i < nidx; i++)
        if (m->indices[i] >= vc && i > bad)
            bad = i;
    if (bad >= 0)
        return sl_fail(err, SL_ERR_RANGE, "raster: index %lld is %u, mesh has %d vertices", bad,
                       (unsigned)m->indices[bad], m->vertex_count);

    rast_vpos *vpos = r->vpos;
    float *vvary = r->vvary;
#pragma omp parallel for schedule(static) num_threads(r->threads)
    for (int i = 0; i < m->vertex_count; i++) {
        sl_vertex_in in = {
            .position = m->positions[i],
            .normal = m->normals ? m->normals[i] : vec3(0, 0, 0),
            .texcoord = m->texcoords ? m->texcoords[i] : vec2(0, 0),
            .index = i,
        };
        rast_vpos *p = &vpos[i];
        float *v = vvary + (size_t)i * (size_t)nvary;
        prog->vertex(d.vs_uniforms, &in, &p->clip, v);
        p->outcode = rast_outcode(p->clip, d.gx, d.gy);
        for (int k = 0; k < nvary; k++)
            if (!isfinite(v[k]))
                p->outcode = RAST_BAD;
        if (p->outcode == 0)
            rast_to_window(&d, p->clip, &p->X, &p->Y, &p->z, &p->iw);
    }
    d.vpos = vpos;
    d.vvary = vvary;

    int nchunks = r->chunk_count;
    rast_chunk *chunks = r->chunks;
    bool oom = false;
    for (int first = 0; first < m->triangle_count && !oom; first += RAST_BATCH) {
        int count = m->triangle_count - first < RAST_BATCH ? m->triangle_count - first : RAST_BATCH;
#pragma omp parallel for schedule(static) num_threads(r->threads)
        for (int c = 0; c < nchunks; c++) {
            rast_chunk *ch = &chunks[c];
            ch->tri_count = 0;
            ch->vary_count = 0;
            for (int t = 0; t < tiles; t++)
                ch->bins[t].count = 0;
            memset(&ch->stats, 0, sizeof ch->stats);
            int lo = first + (int)((long long)count * c / nchunks);
            int hi = first + (int)((long long)count * (c + 1) / nchunks);
            rast_setup_range(&d, ch, lo, hi);
        }
        for (int c = 0; c < nchunks; c++)
            oom |= chunks[c].oom;
        if (oom)
            break;
#pragma omp parallel for schedule(dynamic) num_threads(r->threads)
        for (int t = 0; t < tiles; t++)
            rast_tile(&d, chunks, nchunks, t, &r->tasks[omp_get_thread_num()]);
        if (r->stats_on)
            for (int c = 0; c < nchunks; c++)
                rast_stats_add(&r->stats, &chunks[c].stats);
    }
    if (r->stats_on)
        for (int i = 0; i < r->threads; i++)
            rast_stats_add(&r->stats, &r->tasks[i].stats);
    for (int i = 0; i < r->threads; i++)
        memset(&r->tasks[i].stats, 0, sizeof r->tasks[i].stats);
    if (oom) {
        for (int c = 0; c < nchunks; c++)
            chunks[c].oom = false;
        return sl_fail(err, SL_ERR_MEMORY, "raster: out of memory while binning");
    }
    return true;
}
