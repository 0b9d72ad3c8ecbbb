/* raster.c - the rasterizer context and the draw calls that drive the stages.
 *
 * sl_raster_draw_list (sl_raster_draw is a list of one): validate, check every index
 * and run each draw's vertex shader over its vertices, each in one pass over the whole
 * list (parallel, each vertex written once by one thread; a small list on the calling
 * thread, RAST_PARALLEL_MIN), then for each batch of RAST_BATCH triangles of the whole list: set up
 * and bin one contiguous slice per thread into its own chunk (setup.c), and
 * rasterize the tiles in parallel (tile.c). Chunks are read back in
 * slice order, so bins hold triangles in submission order for any thread count.
 * Batching bounds the memory of set-up triangles (128 bytes and 12 a varying each). A clear
 * (sl_draw.clear) is done by the first batch's tile pass, tile by tile (tile.c).
 * A list is drawn in one tile pass per batch rather than one per draw: each tile's
 * depth is loaded and stored, and its texels go through the cache, once per batch,
 * and there are 2 barriers per batch instead of per draw. */
#include "rast_internal.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

void sl_rast_stats_add(sl_raster_stats *to, const sl_raster_stats *from)
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
    to->fragments_discarded += from->fragments_discarded;
    to->fragments_late_z += from->fragments_late_z;
    to->quads += from->quads;
    to->quad_rounds += from->quad_rounds;
    to->helper_invocations += from->helper_invocations;
    to->parallel_regions += from->parallel_regions;
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
    r->plain = dd.plain;
    r->chunk_count = r->threads;
    r->chunks = aligned_alloc(RAST_CACHE_LINE, (size_t)r->chunk_count * sizeof *r->chunks);
    r->tasks = aligned_alloc(RAST_CACHE_LINE, (size_t)r->threads * sizeof *r->tasks);
    bool ok = r->chunks && r->tasks;
    if (r->chunks)
        memset(r->chunks, 0, (size_t)r->chunk_count * sizeof *r->chunks);
    if (r->tasks)
        memset(r->tasks, 0, (size_t)r->threads * sizeof *r->tasks);
    for (int i = 0; ok && i < r->threads; i++) {
        ok = (r->tasks[i].depth = calloc((size_t)ts * (size_t)ts + RAST_SPAN_MIN_WIDTH, sizeof(float))) != NULL;
        ok = ok && (r->tasks[i].quad = malloc(sizeof(sl_quad))) != NULL;
        if (ok && !r->plain)
            ok = (r->tasks[i].span = aligned_alloc(RAST_CACHE_LINE, sizeof(rast_span))) != NULL &&
                 (r->tasks[i].quads = aligned_alloc(RAST_CACHE_LINE, sizeof(rast_quads))) != NULL;
        if (ok && !r->plain) /* zeroed: tile.c small_tri_spans reads lanes past what it packed */
            memset(r->tasks[i].span, 0, sizeof(rast_span));
    }
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
    for (int i = 0; r->tasks && i < r->threads; i++) {
        free(r->tasks[i].depth);
        free(r->tasks[i].span);
        free(r->tasks[i].quads);
        free(r->tasks[i].quad);
        free(r->tasks[i].scratch);
    }
    free(r->clear_row);
    free(r->chunks);
    free(r->tasks);
    free(r->vpos);
    free(r->vvary);
    free(r->calls);
    free(r);
}

int sl_raster_threads(const sl_raster *r) { return r->threads; }
void sl_raster_keep_extra(sl_raster *r, bool keep) { r->keep_extra = keep; }
bool sl_raster_keeps_extra(const sl_raster *r) { return r->keep_extra; }
int sl_raster_tile_size(const sl_raster *r) { return r->tile_size; }
sl_raster_stats sl_raster_get_stats(const sl_raster *r) { return r->stats; }
void sl_raster_reset_stats(sl_raster *r) { memset(&r->stats, 0, sizeof r->stats); }

static bool validate_target(const sl_target *t, sl_error *err)
{
    if (!t)
        return sl_fail(err, SL_ERR_RANGE, "raster: draw without target");
    if (t->width < 1 || t->height < 1 || t->width > SL_RASTER_MAX_SIZE || t->height > SL_RASTER_MAX_SIZE)
        return sl_fail(err, SL_ERR_RANGE, "raster: target %dx%d outside 1..%d", t->width, t->height,
                       SL_RASTER_MAX_SIZE);
    if (!t->texels || t->texel_size == 0)
        return sl_fail(err, SL_ERR_RANGE, "raster: target without texels");
    if (t->depth_offset != SL_NO_DEPTH &&
        (t->depth_offset < 0 || (size_t)t->depth_offset + sizeof(float) > t->texel_size))
        return sl_fail(err, SL_ERR_RANGE, "raster: depth offset %ld outside a %zu-byte texel", t->depth_offset,
                       t->texel_size);
    return true;
}

static bool validate_draw(const sl_draw *d, sl_error *err)
{
    if (!d || !d->program || !d->mesh)
        return sl_fail(err, SL_ERR_RANGE, "raster: draw without program or mesh");
    const sl_program *p = d->program;
    if (!p->vertex || !p->fragment)
        return sl_fail(err, SL_ERR_RANGE, "raster: program without vertex or fragment shader");
    if (p->fragment_quad && !p->derivatives)
        return sl_fail(err, SL_ERR_RANGE, "raster: a quad form (fragment_quad) without derivatives = true");
    if (p->fragment_quads && !p->derivatives)
        return sl_fail(err, SL_ERR_RANGE, "raster: a multi-quad form (fragment_quads) without derivatives = true");
    if (p->varying_count < 0 || p->varying_count > SL_MAX_VARYINGS)
        return sl_fail(err, SL_ERR_RANGE, "raster: %d varyings (at most %d)", p->varying_count, SL_MAX_VARYINGS);
    const sl_mesh *m = d->mesh;
    if (m->vertex_count < 0 || m->triangle_count < 0 || (m->triangle_count > 0 && (!m->indices || !m->positions)))
        return sl_fail(err, SL_ERR_RANGE, "raster: mesh without positions or indices");
    return true;
}

/* Make room for the vertex stage (nv vertices, nf varying floats), for the draws, for
 * one bin per tile in every chunk and for a tile row of clear texels (clear_bytes, 0
 * when the list does not clear). */
static bool reserve(sl_raster *r, size_t nv, size_t nf, int calls, int tiles, size_t clear_bytes,
                    size_t scratch_bytes, sl_error *err)
{
    for (int i = 0; i < r->threads; i++) {
        rast_task *t = &r->tasks[i];
        if (scratch_bytes <= t->scratch_cap)
            continue;
        char *sc = realloc(t->scratch, scratch_bytes);
        if (!sc)
            return sl_fail(err, SL_ERR_MEMORY, "raster: out of memory for %zu bytes of quad texels", scratch_bytes);
        t->scratch = sc;
        t->scratch_cap = scratch_bytes;
    }
    if (clear_bytes > r->clear_row_cap) {
        char *row = realloc(r->clear_row, clear_bytes);
        if (!row)
            return sl_fail(err, SL_ERR_MEMORY, "raster: out of memory for %zu bytes of clear texels", clear_bytes);
        r->clear_row = row;
        r->clear_row_cap = clear_bytes;
    }
    if (calls > r->call_cap) {
        rast_call *c = realloc(r->calls, (size_t)calls * sizeof *c);
        if (!c)
            return sl_fail(err, SL_ERR_MEMORY, "raster: out of memory for %d draws", calls);
        r->calls = c;
        r->call_cap = calls;
    }
    if (nv > r->vertex_cap) {
        rast_vpos *vp = realloc(r->vpos, nv * sizeof *vp);
        if (!vp)
            return sl_fail(err, SL_ERR_MEMORY, "raster: out of memory for %zu vertices", nv);
        r->vpos = vp;
        r->vertex_cap = nv;
    }
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

/* The last call whose first element (triangle or vertex, by `vertex`) is at or before `at`. */
static int call_at(const rast_call *calls, int count, long long at, bool vertex)
{
    int lo = 0, hi = count - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        long long first = vertex ? (long long)calls[mid].first_vertex : calls[mid].first_tri;
        if (first <= at)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

/* Index check, slice c of n over the list's 3 * tri_count indices: the first draw with an index
 * out of range and, in it, the last bad position (what one draw's check reports). */
static void check_slice(const rast_draw *d, int c, int n, rast_task *task)
{
    long long total = 3 * d->tri_count, lo = total * c / n, hi = total * (c + 1) / n;
    task->bad_call = -1;
    task->bad_at = -1;
    for (int i = lo < hi ? call_at(d->calls, d->call_count, lo / 3, false) : d->call_count;
         i < d->call_count && task->bad_call < 0; i++) {
        const rast_call *call = &d->calls[i];
        long long first = 3 * call->first_tri, end = first + 3LL * call->mesh->triangle_count;
        if (first >= hi)
            break;
        const uint32_t *idx = call->mesh->indices;
        uint32_t vc = (uint32_t)call->mesh->vertex_count;
        for (long long g = first > lo ? first : lo; g < end && g < hi; g++)
            if (idx[g - first] >= vc) {
                task->bad_call = i;
                task->bad_at = g - first;
            }
    }
}

/* Vertex stage, slice c of n over the list's vertices: each vertex is shaded once, by one
 * thread, whichever slice holds it. */
static void shade_slice(const rast_draw *d, size_t nv, int c, int n)
{
    size_t lo = nv * (size_t)c / (size_t)n, hi = nv * (size_t)(c + 1) / (size_t)n;
    for (int i = lo < hi ? call_at(d->calls, d->call_count, (long long)lo, true) : d->call_count;
         i < d->call_count; i++) {
        const rast_call *call = &d->calls[i];
        const sl_mesh *m = call->mesh;
        if (call->first_vertex >= hi)
            break;
        size_t k0 = lo > call->first_vertex ? lo - call->first_vertex : 0;
        size_t k1 = hi - call->first_vertex < (size_t)m->vertex_count ? hi - call->first_vertex
                                                                      : (size_t)m->vertex_count;
        /* the list's own output buffers (sl_raster.vpos, .vvary), read-only for the later stages */
        rast_vpos *vpos = (rast_vpos *)call->vpos;
        float *vvary = (float *)call->vvary;
        for (size_t k = k0; k < k1; k++) {
            sl_vertex_in in = {
                .position = m->positions[k],
                .normal = m->normals ? m->normals[k] : vec3(0, 0, 0),
                .texcoord = m->texcoords ? m->texcoords[k] : vec2(0, 0),
                .tangent = m->tangents ? m->tangents[k] : vec4(0, 0, 0, 0),
                .index = (int)k,
            };
            rast_vpos *p = &vpos[k];
            float *v = vvary + k * (size_t)call->nvary;
            call->program->vertex(call->vs_uniforms, &in, &p->clip, v);
            p->outcode = sl_rast_outcode(p->clip, d->gx, d->gy);
            for (int j = 0; j < call->nvary; j++)
                if (!isfinite(v[j]))
                    p->outcode = RAST_BAD;
            if (p->outcode == 0) {
                rast_to_window(d->target, p->clip, &p->X, &p->Y);
                p->win = rast_window_exact(d->target, p->clip);
            }
        }
    }
}

/* How many slices a stage of `work` (in vertices' worth: RAST_WORK_*) gets: one per thread, or one
 * when the work is too small to pay for a parallel region (RAST_PARALLEL_MIN); counts the region it
 * will open. */
static int stage_slices(sl_raster *r, long long work)
{
    bool parallel = r->threads > 1 && work >= RAST_PARALLEL_MIN;
    if (parallel && r->stats_on)
        r->stats.parallel_regions++;
    return parallel ? r->threads : 1;
}

/* Draws [first, first + count) of a list of `total` into the target, the first of them
 * (only) possibly clearing. Each stage is one pass over the whole segment, whatever its number
 * of draws: a parallel region per stage, not per draw. Regions per draw cost a fork and a
 * barrier each: 300,000 tiny boxes drawn that way take 32 s with 2 threads on a loaded
 * machine, against 1.3 s with one (bench_raster --boxes). */
static bool draw_segment(sl_raster *r, const sl_target *target, const sl_draw *list, int first, int count, int total,
                         sl_error *err)
{
    const sl_draw *draws = list + first;
    size_t nv = 0, nf = 0;
    long long ntri = 0;
    for (int i = 0; i < count; i++) {
        nv += (size_t)draws[i].mesh->vertex_count;
        nf += (size_t)draws[i].mesh->vertex_count * (size_t)draws[i].program->varying_count;
        ntri += draws[i].mesh->triangle_count;
    }
    rast_draw d = {
        .target = target,
        .calls = NULL,
        .call_count = count,
        .tri_count = ntri,
        .gx = 2.0f * RAST_GUARD_PX / (float)target->width - 1.0f,
        .gy = 2.0f * RAST_GUARD_PX / (float)target->height - 1.0f,
        .tile_size = r->tile_size,
        .tile_shift = r->tile_shift,
        .tiles_x = (target->width + r->tile_size - 1) >> r->tile_shift,
        .tiles_y = (target->height + r->tile_size - 1) >> r->tile_shift,
        .stats = r->stats_on,
        .spans = !r->plain,
    };
    int tiles = d.tiles_x * d.tiles_y;
    size_t clear_bytes = draws[0].clear ? (size_t)r->tile_size * target->texel_size : 0;
    /* a quad's 4 lanes (or one discarding fragment) write scratch texels first; a multi-quad
     * shader's lanes, up to SL_QUAD_LANES */
    size_t scratch_bytes = 0;
    d.depth_written = true;
    for (int i = 0; i < count; i++) {
        const sl_program *p = draws[i].program;
        d.depth_written &= p->writes_depth;
        size_t lanes = p->derivatives && p->fragment_quads ? SL_QUAD_LANES : 4;
        if ((p->derivatives || p->discards) && lanes * target->texel_size > scratch_bytes)
            scratch_bytes = lanes * target->texel_size;
    }
    if (!reserve(r, nv, nf, count, tiles, clear_bytes, scratch_bytes, err))
        return false;

    /* Where each draw's triangles and vertex stage output lie in the list's. */
    size_t vbase = 0, fbase = 0;
    long long tbase = 0;
    for (int i = 0; i < count; i++) {
        const sl_draw *dr = &draws[i];
        r->calls[i] = (rast_call){
            .program = dr->program,
            .vs_uniforms = dr->vs_uniforms,
            .fs_uniforms = dr->fs_uniforms,
            .mesh = dr->mesh,
            .cull = dr->cull,
            .nvary = dr->program->varying_count,
            .first_tri = tbase,
            .first_vertex = vbase,
            .vpos = r->vpos + vbase,
            .vvary = r->vvary + fbase,
        };
        vbase += (size_t)dr->mesh->vertex_count;
        fbase += (size_t)dr->mesh->vertex_count * (size_t)dr->program->varying_count;
        tbase += dr->mesh->triangle_count;
    }
    d.calls = r->calls;

    /* Indices: a bad one is an error, not a crash, found before any vertex is shaded. The
     * first draw with one is named, with its last bad index. */
    int n = stage_slices(r, 3 * ntri / RAST_WORK_INDICES);
#pragma omp parallel for schedule(static) num_threads(r->threads) if (n > 1)
    for (int c = 0; c < n; c++)
        check_slice(&d, c, n, &r->tasks[c]);
    int bad_call = -1;
    long long bad_at = -1;
    for (int c = 0; c < n; c++) {
        const rast_task *t = &r->tasks[c];
        if (t->bad_call >= 0 && (bad_call < 0 || t->bad_call < bad_call))
            bad_call = t->bad_call, bad_at = t->bad_at;
        else if (t->bad_call >= 0 && t->bad_call == bad_call && t->bad_at > bad_at)
            bad_at = t->bad_at;
    }
    if (bad_call >= 0) {
        const sl_mesh *m = draws[bad_call].mesh;
        sl_fail(err, SL_ERR_RANGE, "raster: index %lld is %u, mesh has %d vertices", bad_at,
                (unsigned)m->indices[bad_at], m->vertex_count);
        if (total > 1)
            sl_error_prefix(err, "draw %d: ", first + bad_call);
        return false;
    }

    /* The vertex stage, over the list's vertices. */
    n = stage_slices(r, (long long)nv);
#pragma omp parallel for schedule(static) num_threads(r->threads) if (n > 1)
    for (int c = 0; c < n; c++)
        shade_slice(&d, nv, c, n);

    /* The clear rides on the first batch's tile pass, which then visits every tile (a
     * list without triangles still has that one batch). */
    if (draws[0].clear) {
        for (int i = 0; i < r->tile_size; i++)
            memcpy(r->clear_row + (size_t)i * target->texel_size, draws[0].clear, target->texel_size);
        d.clear_row = r->clear_row;
        d.clear_depth = 1.0f;
        if (target->depth_offset != SL_NO_DEPTH)
            memcpy(&d.clear_depth, (const char *)draws[0].clear + target->depth_offset, sizeof(float));
    }

    /* Set-up chunks are the same slices of each batch however many threads run them, so the
     * bins, and the result, do not depend on the thread count. */
    int nchunks = r->chunk_count;
    rast_chunk *chunks = r->chunks;
    bool oom = false;
    for (long long b0 = 0; (b0 < ntri || (b0 == 0 && d.clear_row)) && !oom; b0 += RAST_BATCH) {
        long long nb = ntri - b0 < RAST_BATCH ? ntri - b0 : RAST_BATCH;
        n = stage_slices(r, nb * RAST_WORK_TRIANGLE);
#pragma omp parallel for schedule(static) num_threads(r->threads) if (n > 1)
        for (int c = 0; c < nchunks; c++) {
            rast_chunk *ch = &chunks[c];
            ch->tri_count = 0;
            ch->vary_count = 0;
            for (int t = 0; t < tiles; t++)
                ch->bins[t].count = 0;
            memset(&ch->stats, 0, sizeof ch->stats);
            long long lo = b0 + nb * c / nchunks;
            long long hi = b0 + nb * (c + 1) / nchunks;
            sl_rast_setup_range(&d, ch, lo, hi);
        }
        long long binned = 0;
        for (int c = 0; c < nchunks; c++) {
            oom |= chunks[c].oom;
            binned += chunks[c].tri_count;
        }
        if (oom)
            break;
        /* The tile pass: its work is the pixels covered, not the triangles, so it is parallel
         * whenever anything was binned (or the target is cleared). */
        if (binned > 0 || d.clear_row) {
            n = stage_slices(r, RAST_PARALLEL_MIN);
#pragma omp parallel for schedule(dynamic) num_threads(r->threads) if (n > 1)
            for (int t = 0; t < tiles; t++)
                sl_rast_tile(&d, chunks, nchunks, t, &r->tasks[omp_get_thread_num()]);
        }
        d.clear_row = NULL;
        if (r->stats_on)
            for (int c = 0; c < nchunks; c++)
                sl_rast_stats_add(&r->stats, &chunks[c].stats);
    }
    if (r->stats_on)
        for (int i = 0; i < r->threads; i++)
            sl_rast_stats_add(&r->stats, &r->tasks[i].stats);
    for (int i = 0; i < r->threads; i++)
        memset(&r->tasks[i].stats, 0, sizeof r->tasks[i].stats);
    if (oom) {
        for (int c = 0; c < nchunks; c++)
            chunks[c].oom = false;
        return sl_fail(err, SL_ERR_MEMORY, "raster: out of memory while binning");
    }
    return true;
}

bool sl_raster_draw_list(sl_raster *r, const sl_target *target, const sl_draw *draws, int count, sl_error *err)
{
    if (!validate_target(target, err))
        return false;
    if (count < 0 || (count > 0 && !draws))
        return sl_fail(err, SL_ERR_RANGE, "raster: %d draws", count);
    for (int i = 0; i < count; i++)
        if (!validate_draw(&draws[i], err)) {
            if (count > 1)
                sl_error_prefix(err, "draw %d: ", i);
            return false;
        }
    /* A draw that clears starts a new segment: everything before it is drawn first.
     * So does every RAST_MAX_CALLS-th draw. */
    for (int i = 0; i < count;) {
        int j = i + 1;
        while (j < count && !draws[j].clear && j - i < RAST_MAX_CALLS)
            j++;
        if (!draw_segment(r, target, draws, i, j - i, count, err))
            return false;
        i = j;
    }
    return true;
}

bool sl_raster_draw(sl_raster *r, const sl_target *target, const sl_draw *draw, sl_error *err)
{
    if (!draw)
        return sl_fail(err, SL_ERR_RANGE, "raster: draw without program or mesh");
    return sl_raster_draw_list(r, target, draw, 1, err);
}
