/* obj.c - Wavefront OBJ reader: the subset that describes one triangle mesh.
 *
 * Reads v, vt, vn and f (forms v, v/t, v//n, v/t/n; negative indices count back from the
 * last element defined so far; positive ones may also name elements defined later in the
 * file, and such faces are built once the file has been read). Polygons are triangulated in
 * their best-fit plane: convex ones as the fan (0, i, i+1), concave ones by ear clipping;
 * self-intersecting ones are an error naming the face. Comments and statements that carry no
 * geometry for softlight (o, g, s, usemtl, mtllib, l, p and the other keywords) are skipped,
 * but a keyword that is not one (bytes glued to v or f, a stray byte-order mark) is an error,
 * so that no data is lost without a word. Text: a UTF-8 byte-order mark is skipped; LF, CRLF
 * and CR end a line; a backslash at the end of a line continues it (OBJ specification, B1);
 * UTF-16 is recognised and refused by name.
 *
 * Output: an indexed sl_mesh with one vertex per distinct (v, vt, vn) triple in order of
 * first use. Normals from the file are normalised; corners without one (or with a zero one)
 * get an angle-weighted normal accumulated per OBJ position, so a texture seam does not split
 * the shading. Errors carry `name:line:` (the first line of a continued statement) and show
 * input bytes with what is not printable ASCII as '?'; sizes are capped (scene_internal.h).
 *
 * Sections, in order: storage, tokens, faces, statements, the mesh, entry points. */
#include "scene_internal.h"

#include "../core/image.h" /* sl_read_file */

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define OBJ_MAX_FILE_BYTES ((size_t)1 << 30)
/* Ear clipping is O(n^2) in the corners of a concave face: 8000 corners take 0.4 s here
 * (Release), and a hostile file could hold many such faces. Convex faces have no cap. */
#define OBJ_MAX_CONCAVE_CORNERS 4096

/* ---- storage: growable arrays, the reader and its corner map ---- */

/* A growable array of fixed-size elements. */
typedef struct {
    void *data;
    size_t count, cap, elem;
} array;

static bool array_push(array *a, const void *item)
{
    if (a->count == a->cap) {
        size_t cap = a->cap ? 2 * a->cap : 256;
        void *grown = realloc(a->data, cap * a->elem);
        if (!grown)
            return false;
        a->data = grown;
        a->cap = cap;
    }
    memcpy((char *)a->data + a->count * a->elem, item, a->elem);
    a->count++;
    return true;
}

/* Room for at least n elements (count is left as it is): per-face scratch. */
static bool array_reserve(array *a, size_t n)
{
    if (n <= a->cap)
        return true;
    void *grown = realloc(a->data, n * a->elem);
    if (!grown)
        return false;
    a->data = grown;
    a->cap = n;
    return true;
}

/* One output vertex: 0-based indices into the file's v, vt, vn lists; -1 = absent. A face
 * read before the elements it names holds them unchecked until the end (pending_face). */
typedef struct {
    int32_t v, t, n;
} corner;

/* Open-addressing map from corner to output vertex index, kept under half full. */
typedef struct {
    uint32_t *slots; /* vertex index + 1; 0 = empty */
    size_t mask;
} corner_map;

/* A face that names an element defined later in the file, or any face after one: its corners
 * are in obj_reader.pending from `first`, and it is built (and its indices checked) at the end. */
typedef struct {
    size_t line, first, count;
} pending_face;

typedef struct {
    const char *name;
    size_t line; /* of the statement being read: its first line when continued with '\' */
    sl_error *err;
    array positions, texcoords, normals; /* vec3, vec2, vec3 as read */
    array corners;                       /* corner, one per output vertex */
    array indices;                       /* uint32_t, 3 per triangle */
    corner_map map;
    bool any_texcoord;
    size_t planned_triangles; /* n - 2 per face read, built or pending: checked against the cap */
    array face;               /* corner: the face being read */
    array face_index;         /* uint32_t: its output vertices */
    array pending;            /* corner: corners of the pending faces */
    array pending_faces;      /* pending_face */
} obj_reader;

static uint32_t corner_hash(corner c)
{
    uint32_t h = (uint32_t)c.v * 0x9E3779B1u;
    h ^= (uint32_t)c.t * 0x85EBCA77u + (h << 6) + (h >> 2);
    h ^= (uint32_t)c.n * 0xC2B2AE3Du + (h << 6) + (h >> 2);
    return h ^ (h >> 15);
}

static bool map_grow(obj_reader *r)
{
    size_t size = r->map.slots ? 2 * (r->map.mask + 1) : 1024;
    uint32_t *slots = calloc(size, sizeof *slots);
    if (!slots)
        return false;
    const corner *cs = r->corners.data;
    for (size_t i = 0; i < r->corners.count; i++) {
        size_t s = corner_hash(cs[i]) & (size - 1);
        while (slots[s])
            s = (s + 1) & (size - 1);
        slots[s] = (uint32_t)i + 1;
    }
    free(r->map.slots);
    r->map.slots = slots;
    r->map.mask = size - 1;
    return true;
}

static bool fail_line(obj_reader *r, sl_error_code code, const char *what, const char *detail)
{
    return sl_fail(r->err, code, "%s:%zu: %s%s", r->name, r->line, what, detail ? detail : "");
}

/* Up to 32 bytes of input for a message, masked (sl_error_excerpt). */
static const char *excerpt(const char *s, char out[40]) { return sl_error_excerpt(s, 32, out, 40); }

/* The output vertex for a corner, creating it on first use. */
static bool vertex_for(obj_reader *r, corner c, uint32_t *index)
{
    if (!r->map.slots || 2 * (r->corners.count + 1) > r->map.mask + 1) {
        if (!map_grow(r))
            return fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
    }
    const corner *cs = r->corners.data;
    size_t s = corner_hash(c) & r->map.mask;
    while (r->map.slots[s]) {
        const corner *o = &cs[r->map.slots[s] - 1];
        if (o->v == c.v && o->t == c.t && o->n == c.n) {
            *index = r->map.slots[s] - 1;
            return true;
        }
        s = (s + 1) & r->map.mask;
    }
    if (r->corners.count >= SCENE_MAX_VERTICES) {
        char detail[64];
        snprintf(detail, sizeof detail, " (%d)", SCENE_MAX_VERTICES);
        return fail_line(r, SL_ERR_RANGE, "too many distinct vertices", detail);
    }
    if (!array_push(&r->corners, &c))
        return fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
    r->map.slots[s] = (uint32_t)r->corners.count;
    *index = (uint32_t)r->corners.count - 1;
    return true;
}

/* ---- tokens, numbers and indices ---- */

static bool is_space(char ch) { return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\v' || ch == '\f'; }

/* Next whitespace-separated token of a NUL-terminated line, or NULL at its end. */
static char *next_token(char **cursor)
{
    char *p = *cursor;
    while (is_space(*p))
        p++;
    if (!*p)
        return NULL;
    char *start = p;
    while (*p && !is_space(*p))
        p++;
    if (*p)
        *p++ = '\0';
    *cursor = p;
    return start;
}

/* Read between `min` and `max` numbers (more are ignored, e.g. vertex colours after v x y z). */
static bool read_numbers(obj_reader *r, char **cursor, int min, int max, float *out, int *got)
{
    int n = 0;
    char *tok;
    while ((tok = next_token(cursor)) != NULL) {
        if (n == max)
            continue;
        char *end;
        float x = strtof(tok, &end); /* overflow gives inf, rejected below; underflow is harmless */
        if (end == tok || *end) {
            /* '3.1+e2': tinyobjloader, assimp and strtod read 3.1 and drop the rest, likely
             * losing a 310. Refused here, with the spelling that was probably meant. */
            char ex[40], hint[80] = "";
            if (end != tok && (end[0] == '+' || end[0] == '-') && (end[1] == 'e' || end[1] == 'E') && end[2] &&
                strspn(end + 2, "0123456789") == strlen(end + 2) && end - tok <= 24 && strlen(end + 2) <= 8)
                snprintf(hint, sizeof hint, " (an exponent is written %.*s%c%c%s)", (int)(end - tok), tok, end[1],
                         end[0], end + 2);
            char detail[160];
            snprintf(detail, sizeof detail, "'%s'%s", excerpt(tok, ex), hint);
            return fail_line(r, SL_ERR_FORMAT, "expected a number, got ", detail);
        }
        if (!isfinite(x)) {
            char ex[40], detail[64];
            snprintf(detail, sizeof detail, " ('%s')", excerpt(tok, ex));
            return fail_line(r, SL_ERR_FORMAT, "number is not finite", detail);
        }
        out[n++] = x;
    }
    if (n < min) {
        char detail[64];
        snprintf(detail, sizeof detail, "expected %d numbers, got %d", min, n);
        return fail_line(r, SL_ERR_FORMAT, detail, NULL);
    }
    *got = n;
    return true;
}

/* Resolve one OBJ index (1-based, or negative = relative to `count`, the elements defined so
 * far) to 0-based. A positive index past `count` that could still be defined later is a
 * forward reference: *forward is set and check_pending tests it at the end of the file. */
static bool resolve_index(obj_reader *r, const char *text, const char *kind, size_t count, int32_t *out,
                          bool *forward)
{
    char *end;
    errno = 0;
    long i = strtol(text, &end, 10);
    if (end == text || *end) {
        char ex[40], detail[128];
        snprintf(detail, sizeof detail, "%s index: expected an integer, got '%s'", kind, excerpt(text, ex));
        return fail_line(r, SL_ERR_FORMAT, detail, NULL);
    }
    long resolved = i > 0 ? i - 1 : (long)count + i;
    if (errno != ERANGE && i > 0 && (size_t)resolved >= count && resolved < SCENE_MAX_VERTICES) {
        *forward = true;
        *out = (int32_t)resolved;
        return true;
    }
    if (errno == ERANGE || i == 0 || resolved < 0 || (size_t)resolved >= count) {
        char detail[128];
        if (count == 0)
            snprintf(detail, sizeof detail, "%s index %.24s out of range (none defined yet)", kind, text);
        else if (i < 0)
            snprintf(detail, sizeof detail, "%s index %.24s out of range (-%zu..-1)", kind, text, count);
        else
            snprintf(detail, sizeof detail, "%s index %.24s out of range (1..%zu)", kind, text, count);
        return fail_line(r, SL_ERR_FORMAT, detail, NULL);
    }
    *out = (int32_t)resolved;
    return true;
}

/* An index of a pending face against the file's final count (-1 = absent). */
static bool check_pending(obj_reader *r, int32_t index, const char *kind, size_t count)
{
    if (index < 0 || (size_t)index < count)
        return true;
    char detail[128];
    if (count == 0)
        snprintf(detail, sizeof detail, "%s index %ld out of range (the file defines none)", kind, (long)index + 1);
    else
        snprintf(detail, sizeof detail, "%s index %ld out of range (1..%zu)", kind, (long)index + 1, count);
    return fail_line(r, SL_ERR_FORMAT, detail, NULL);
}

/* Parse one face vertex: v, v/t, v//n or v/t/n. */
static bool parse_corner(obj_reader *r, char *tok, corner *c, bool *forward)
{
    char *parts[3] = {tok, NULL, NULL};
    int n = 1;
    for (char *p = tok; *p; p++) {
        if (*p == '/') {
            if (n == 3)
                break;
            *p = '\0';
            parts[n++] = p + 1;
        }
    }
    c->t = c->n = -1;
    if (n == 3 && strchr(parts[2], '/')) {
        char ex[40], detail[64];
        snprintf(detail, sizeof detail, "'%s'", excerpt(tok, ex));
        return fail_line(r, SL_ERR_FORMAT, "malformed face vertex ", detail);
    }
    if (!resolve_index(r, parts[0], "face", r->positions.count, &c->v, forward))
        return false;
    if (n >= 2 && parts[1][0]) {
        if (!resolve_index(r, parts[1], "texture coordinate", r->texcoords.count, &c->t, forward))
            return false;
        r->any_texcoord = true;
    }
    if (n == 3) {
        if (!parts[2][0])
            return fail_line(r, SL_ERR_FORMAT, "malformed face vertex: empty normal index after '/'", NULL);
        if (!resolve_index(r, parts[2], "normal", r->normals.count, &c->n, forward))
            return false;
    } else if (n == 2 && !parts[1][0]) {
        return fail_line(r, SL_ERR_FORMAT, "malformed face vertex: empty texture coordinate index after '/'",
                         NULL);
    }
    return true;
}

/* ---- faces: fans, ear clipping, faces pending on later elements ---- */

static bool push_triangle(obj_reader *r, uint32_t a, uint32_t b, uint32_t c)
{
    uint32_t tri[3] = {a, b, c};
    for (int k = 0; k < 3; k++)
        if (!array_push(&r->indices, &tri[k]))
            return fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
    return true;
}

/* The fan (0, i, i+1): convex faces, and faces whose corners all lie on one line. */
static bool push_fan(obj_reader *r, const uint32_t *idx, size_t n)
{
    for (size_t i = 1; i + 1 < n; i++)
        if (!push_triangle(r, idx[0], idx[i], idx[i + 1]))
            return false;
    return true;
}

/* A face being triangulated: its corners projected onto its best-fit plane so that it runs
 * counter-clockwise, and a ring of prev/next links from which clipped corners are unlinked. */
typedef struct {
    const double *u, *v;
    uint32_t *prev, *next;
} ring;

/* Twice the signed area of (a, b, c): > 0 when counter-clockwise. Coordinates are floats made
 * relative to corner 0 in double, so these products neither overflow nor lose the sign of
 * anything but near-collinear corners. */
static double orient(const ring *g, uint32_t a, uint32_t b, uint32_t c)
{
    return (g->u[b] - g->u[a]) * (g->v[c] - g->v[a]) - (g->v[b] - g->v[a]) * (g->u[c] - g->u[a]);
}

static bool same_point(const ring *g, uint32_t a, uint32_t b) { return g->u[a] == g->u[b] && g->v[a] == g->v[b]; }

/* Whether corner q, seen from corner x, lies strictly inside the angle of a counter-clockwise
 * triangle at x, whose other corners are y (next) and z (previous). */
static bool in_angle(const ring *g, uint32_t x, uint32_t y, uint32_t z, uint32_t q)
{
    return orient(g, x, y, q) > 0.0 && orient(g, x, z, q) < 0.0;
}

/* Whether corner b can be cut off with its neighbours as the triangle (a, b, c). A
 * zero-area corner (on a line with its neighbours, a spike, a repeated corner) always can:
 * the covered region does not change. Otherwise b must turn left and no other corner may
 * block the triangle: a reflex or straight one inside it or on its edges (in a simple polygon
 * a triangle holding any corner holds a reflex one), or, for a corner at the same place as
 * a, b or c (the seam of a face with a hole goes through such pairs), an edge leaving it
 * into the triangle's angle there. */
static bool is_ear(const ring *g, uint32_t b)
{
    uint32_t a = g->prev[b], c = g->next[b];
    double area = orient(g, a, b, c);
    if (area == 0.0)
        return true;
    if (area < 0.0)
        return false;
    double lo_u = fmin(g->u[a], fmin(g->u[b], g->u[c])), hi_u = fmax(g->u[a], fmax(g->u[b], g->u[c]));
    double lo_v = fmin(g->v[a], fmin(g->v[b], g->v[c])), hi_v = fmax(g->v[a], fmax(g->v[b], g->v[c]));
    for (uint32_t p = g->next[c]; p != a; p = g->next[p]) {
        if (g->u[p] < lo_u || g->u[p] > hi_u || g->v[p] < lo_v || g->v[p] > hi_v)
            continue;
        uint32_t pp = g->prev[p], pn = g->next[p];
        if (same_point(g, p, a)) {
            if (in_angle(g, a, b, c, pp) || in_angle(g, a, b, c, pn))
                return false;
        } else if (same_point(g, p, b)) {
            if (in_angle(g, b, c, a, pp) || in_angle(g, b, c, a, pn))
                return false;
        } else if (same_point(g, p, c)) {
            if (in_angle(g, c, a, b, pp) || in_angle(g, c, a, b, pn))
                return false;
        } else if (orient(g, pp, p, pn) <= 0.0 && orient(g, a, b, p) >= 0.0 && orient(g, b, c, p) >= 0.0 &&
                   orient(g, c, a, p) >= 0.0) {
            return false;
        }
    }
    return true;
}

/* Whether the projected face is convex: every turn to the left (zero-length edges skipped,
 * no spike) and one turn around in all, so that a star polygon is not taken for convex. */
static bool is_convex(const double *u, const double *v, size_t n)
{
    double turned = 0.0, pu = 0.0, pv = 0.0, fu = 0.0, fv = 0.0;
    bool first = true;
    for (size_t i = 0; i <= n; i++) {
        double eu, ev;
        if (i < n) {
            size_t j = (i + 1) % n;
            eu = u[j] - u[i];
            ev = v[j] - v[i];
            if (eu == 0.0 && ev == 0.0)
                continue;
        } else {
            eu = fu; /* back to the first edge to close the loop */
            ev = fv;
        }
        if (first) {
            fu = eu;
            fv = ev;
            first = false;
        } else {
            double cr = pu * ev - pv * eu, dt = pu * eu + pv * ev;
            if (cr < 0.0 || (cr == 0.0 && dt < 0.0))
                return false;
            turned += atan2(cr, dt);
        }
        pu = eu;
        pv = ev;
    }
    return fabs(turned - 2.0 * 3.14159265358979323846) < 1e-6;
}

/* Ear clipping of a projected concave face, O(n^2): every corner's ear status once, then
 * only the neighbours of each cut corner, whose status alone can change in a simple polygon. */
static bool clip_ears(obj_reader *r, ring *g, bool *ear, const uint32_t *idx, size_t n, const char *what)
{
    const double *u = g->u, *v = g->v;
    uint32_t *prev = g->prev, *next = g->next;
    bool ok = true;
    /* A simple polygon's edges meet only at shared corners (or overlap along a seam): two
     * that cross make it self-intersecting, and no triangulation has its shape. */
    for (uint32_t i = 0; ok && i < n; i++) {
        uint32_t i2 = next[i];
        for (uint32_t j = i + 2; ok && j < n; j++) {
            uint32_t j2 = next[j];
            if (j2 == i)
                continue;
            if (fmax(u[j], u[j2]) < fmin(u[i], u[i2]) || fmin(u[j], u[j2]) > fmax(u[i], u[i2]) ||
                fmax(v[j], v[j2]) < fmin(v[i], v[i2]) || fmin(v[j], v[j2]) > fmax(v[i], v[i2]))
                continue;
            double d1 = orient(g, i, i2, j), d2 = orient(g, i, i2, j2);
            double d3 = orient(g, j, j2, i), d4 = orient(g, j, j2, i2);
            if (((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))) {
                char detail[96];
                snprintf(detail, sizeof detail, "its edges cross (corners %u-%u and %u-%u)", (unsigned)i + 1,
                         (unsigned)i2 + 1, (unsigned)j + 1, (unsigned)j2 + 1);
                ok = fail_line(r, SL_ERR_FORMAT, what, detail);
            }
        }
    }
    for (uint32_t i = 0; ok && i < n; i++)
        ear[i] = is_ear(g, i);
    size_t left = n;
    uint32_t cur = 0;
    int fresh_looks = 0;
    while (ok && left > 3) {
        uint32_t b = cur;
        for (size_t steps = 0; !ear[b] && steps < left; steps++)
            b = next[b];
        if (!ear[b]) {
            /* Where edges touch (a seam), cutting a corner can also free a non-neighbour:
             * look at every corner again (never needed in 6000 random faces with seams; twice
             * at most, as each look costs O(n^2)). */
            bool any = false;
            for (size_t s = 0; s < left; s++, b = next[b])
                any = (ear[b] = is_ear(g, b)) || any;
            if (!any || ++fresh_looks > 2)
                ok = fail_line(r, SL_ERR_FORMAT, what, "no corner can be cut off (edges that touch or overlap?)");
            continue;
        }
        uint32_t a = prev[b], c = next[b];
        ok = push_triangle(r, idx[a], idx[b], idx[c]);
        next[a] = c;
        prev[c] = a;
        left--;
        ear[a] = is_ear(g, a);
        ear[c] = is_ear(g, c);
        cur = c;
    }
    if (ok)
        ok = push_triangle(r, idx[prev[cur]], idx[cur], idx[next[cur]]);
    return ok;
}

/* Triangulate a face of n > 3 corners (output vertices idx) in the plane of its Newell normal
 * (the best-fit plane of a face that is only roughly planar): convex faces as the fan, as
 * always; concave ones by clip_ears. Triangles keep the face's winding. Errors name the
 * face's line and say why it cannot be triangulated. */
static bool triangulate(obj_reader *r, const corner *cs, const uint32_t *idx, size_t n)
{
    const vec3 *pos = r->positions.data;
    vec3 o = pos[cs[0].v];
    double nrm[3] = {0.0, 0.0, 0.0};
    for (size_t i = 0; i < n; i++) {
        vec3 P = pos[cs[i].v], Q = pos[cs[(i + 1) % n].v];
        double p[3] = {(double)P.x - (double)o.x, (double)P.y - (double)o.y, (double)P.z - (double)o.z};
        double q[3] = {(double)Q.x - (double)o.x, (double)Q.y - (double)o.y, (double)Q.z - (double)o.z};
        nrm[0] += (p[1] - q[1]) * (p[2] + q[2]);
        nrm[1] += (p[2] - q[2]) * (p[0] + q[0]);
        nrm[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
    int k = fabs(nrm[0]) >= fabs(nrm[1]) ? (fabs(nrm[0]) >= fabs(nrm[2]) ? 0 : 2) : (fabs(nrm[1]) >= fabs(nrm[2]) ? 1 : 2);
    char what[96];
    snprintf(what, sizeof what, "face with %zu corners cannot be triangulated: ", n);
    if (nrm[k] == 0.0) {
        /* No area in any plane. Corners on one line draw nothing, like a degenerate triangle:
         * the fan is kept. Otherwise the face folds over itself (a bow tie). */
        for (size_t i = 1; i + 1 < n; i++) {
            vec3 a = sub3(pos[cs[i].v], o), b = sub3(pos[cs[i + 1].v], o);
            vec3 c = cross(a, b);
            if (c.x != 0.0f || c.y != 0.0f || c.z != 0.0f)
                return fail_line(r, SL_ERR_FORMAT, what, "it encloses no area (it folds over itself)");
        }
        return push_fan(r, idx, n);
    }

    /* Project by dropping the normal's largest axis; mirror so the face runs counter-clockwise. */
    double *u = malloc(n * sizeof *u), *v = malloc(n * sizeof *v);
    uint32_t *prev = malloc(n * sizeof *prev), *next = malloc(n * sizeof *next);
    bool *ear = malloc(n * sizeof *ear);
    bool ok = u && v && prev && next && ear;
    if (!ok)
        fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
    for (size_t i = 0; ok && i < n; i++) {
        vec3 P = pos[cs[i].v];
        double p[3] = {(double)P.x - (double)o.x, (double)P.y - (double)o.y, (double)P.z - (double)o.z};
        u[i] = nrm[k] > 0.0 ? p[(k + 1) % 3] : -p[(k + 1) % 3];
        v[i] = p[(k + 2) % 3];
        prev[i] = (uint32_t)((i + n - 1) % n);
        next[i] = (uint32_t)((i + 1) % n);
    }
    if (ok && is_convex(u, v, n)) {
        ok = push_fan(r, idx, n);
    } else if (ok && n > OBJ_MAX_CONCAVE_CORNERS) {
        char detail[96];
        snprintf(detail, sizeof detail, "it is concave and has more than %d corners (split it)",
                 OBJ_MAX_CONCAVE_CORNERS);
        ok = fail_line(r, SL_ERR_RANGE, what, detail);
    } else if (ok) {
        ok = clip_ears(r, &(ring){u, v, prev, next}, ear, idx, n, what);
    }
    free(u);
    free(v);
    free(prev);
    free(next);
    free(ear);
    return ok;
}

/* Make the output vertices of a face's corners and its triangles. */
static bool emit_face(obj_reader *r, const corner *cs, size_t n)
{
    if (!array_reserve(&r->face_index, n))
        return fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
    uint32_t *idx = r->face_index.data;
    for (size_t k = 0; k < n; k++)
        if (!vertex_for(r, cs[k], &idx[k]))
            return false;
    if (n == 3)
        return push_triangle(r, idx[0], idx[1], idx[2]);
    return triangulate(r, cs, idx, n);
}

/* An `f` statement: built now, or kept as a pending_face when it names a later element. */
static bool parse_face(obj_reader *r, char *cursor)
{
    r->face.count = 0;
    bool forward = false;
    char *tok;
    while ((tok = next_token(&cursor)) != NULL) {
        corner c;
        if (!parse_corner(r, tok, &c, &forward))
            return false;
        if (!array_push(&r->face, &c))
            return fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
    }
    size_t n = r->face.count;
    if (n == 0)
        return true; /* an empty `f` carries nothing: skipped, as assimp and tinyobjloader do */
    if (n < 3) {
        char detail[64];
        snprintf(detail, sizeof detail, "a face needs at least 3 vertices, got %zu", n);
        return fail_line(r, SL_ERR_FORMAT, detail, NULL);
    }
    r->planned_triangles += n - 2;
    if (r->planned_triangles > SCENE_MAX_TRIANGLES) {
        char detail[64];
        snprintf(detail, sizeof detail, " (%d)", SCENE_MAX_TRIANGLES);
        return fail_line(r, SL_ERR_RANGE, "too many triangles", detail);
    }
    /* Once one face waits, the later ones wait too, so that triangles keep the file's order. */
    if (!forward && r->pending_faces.count == 0)
        return emit_face(r, r->face.data, n);
    pending_face pf = {.line = r->line, .first = r->pending.count, .count = n};
    const corner *cs = r->face.data;
    for (size_t k = 0; k < n; k++)
        if (!array_push(&r->pending, &cs[k]))
            return fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
    return array_push(&r->pending_faces, &pf) || fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
}

/* Build the pending faces now that every element is defined, in file order. */
static bool build_pending(obj_reader *r)
{
    for (size_t f = 0; f < r->pending_faces.count; f++) {
        pending_face pf = ((const pending_face *)r->pending_faces.data)[f];
        const corner *cs = (const corner *)r->pending.data + pf.first;
        r->line = pf.line;
        for (size_t k = 0; k < pf.count; k++)
            if (!check_pending(r, cs[k].v, "face", r->positions.count) ||
                !check_pending(r, cs[k].t, "texture coordinate", r->texcoords.count) ||
                !check_pending(r, cs[k].n, "normal", r->normals.count))
                return false;
        if (!emit_face(r, cs, pf.count))
            return false;
    }
    return true;
}

/* ---- statements: one line of the file ---- */

/* A statement softlight does not use is skipped when its keyword looks like one: a letter,
 * then letters, digits and '_' (every keyword of the OBJ specification does), and not v, vt,
 * vn or f with a digit glued on. Anything else is data that would be lost without a word. */
static bool skip_statement(obj_reader *r, const char *kw)
{
    bool word = (kw[0] >= 'a' && kw[0] <= 'z') || (kw[0] >= 'A' && kw[0] <= 'Z');
    for (const char *p = kw; word && *p; p++)
        word = (*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') || *p == '_';
    const char *hint = NULL;
    if (word) {
        static const char *const glued[] = {"v", "vt", "vn", "f"};
        for (size_t i = 0; !hint && i < sizeof glued / sizeof glued[0]; i++) {
            size_t len = strlen(glued[i]);
            if (strncmp(kw, glued[i], len) == 0 && kw[len] >= '0' && kw[len] <= '9')
                hint = " (a space missing after the keyword?)";
        }
        if (!hint)
            return true;
    } else if (strncmp(kw, "\xef\xbb\xbf", 3) == 0) {
        hint = " (a UTF-8 byte-order mark inside the file?)";
    } else {
        hint = " (expected a keyword such as v, vt, vn or f: a letter, then letters, digits or '_')";
    }
    char ex[40], detail[192];
    snprintf(detail, sizeof detail, "unknown statement '%s'%s", excerpt(kw, ex), hint);
    return fail_line(r, SL_ERR_FORMAT, detail, NULL);
}

static bool parse_line(obj_reader *r, char *line)
{
    char *hash = strchr(line, '#');
    if (hash)
        *hash = '\0';
    char *cursor = line;
    char *keyword = next_token(&cursor);
    if (!keyword)
        return true;
    float x[4];
    int got;
    if (strcmp(keyword, "v") == 0) {
        if (!read_numbers(r, &cursor, 3, 3, x, &got))
            return false;
        if (r->positions.count >= SCENE_MAX_VERTICES)
            return fail_line(r, SL_ERR_RANGE, "too many positions", NULL);
        vec3 p = vec3(x[0], x[1], x[2]);
        return array_push(&r->positions, &p) || fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
    }
    if (strcmp(keyword, "vt") == 0) {
        if (!read_numbers(r, &cursor, 1, 2, x, &got))
            return false;
        if (r->texcoords.count >= SCENE_MAX_VERTICES)
            return fail_line(r, SL_ERR_RANGE, "too many texture coordinates", NULL);
        vec2 t = vec2(x[0], got > 1 ? x[1] : 0.0f);
        return array_push(&r->texcoords, &t) || fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
    }
    if (strcmp(keyword, "vn") == 0) {
        if (!read_numbers(r, &cursor, 3, 3, x, &got))
            return false;
        if (r->normals.count >= SCENE_MAX_VERTICES)
            return fail_line(r, SL_ERR_RANGE, "too many normals", NULL);
        /* A zero normal is kept as zero and later replaced by a computed one. */
        vec3 n = vec3(x[0], x[1], x[2]);
        if (!sl_scene_safe_normalize(n, &n))
            n = vec3s(0.0f);
        return array_push(&r->normals, &n) || fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
    }
    if (strcmp(keyword, "f") == 0)
        return parse_face(r, cursor);
    return skip_statement(r, keyword); /* o, g, s, usemtl, mtllib, l, p, ... carry nothing we use */
}

/* ---- the mesh ---- */

static void reader_free(obj_reader *r)
{
    free(r->positions.data);
    free(r->texcoords.data);
    free(r->normals.data);
    free(r->corners.data);
    free(r->indices.data);
    free(r->map.slots);
    free(r->face.data);
    free(r->face_index.data);
    free(r->pending.data);
    free(r->pending_faces.data);
}

/* Turn the parsed lists into the output mesh. */
static bool build_mesh(obj_reader *r, sl_mesh *mesh)
{
    int nv = (int)r->corners.count, nt = (int)(r->indices.count / 3);
    if (!sl_scene_mesh_alloc(mesh, nv, nt, r->any_texcoord, r->name, r->err))
        return false;
    const corner *cs = r->corners.data;
    const vec3 *pos = r->positions.data, *nrm = r->normals.data;
    const vec2 *tex = r->texcoords.data;
    bool *keep = malloc((size_t)nv * sizeof *keep);
    uint32_t *group = malloc((size_t)nv * sizeof *group);
    if (!keep || !group) {
        free(keep);
        free(group);
        sl_mesh_free(mesh);
        return sl_fail(r->err, SL_ERR_MEMORY, "%s: out of memory", r->name);
    }
    bool all_kept = true;
    for (int v = 0; v < nv; v++) {
        mesh->positions[v] = pos[cs[v].v];
        if (mesh->texcoords)
            mesh->texcoords[v] = cs[v].t >= 0 ? tex[cs[v].t] : vec2(0.0f, 0.0f);
        vec3 n = cs[v].n >= 0 ? nrm[cs[v].n] : vec3s(0.0f);
        keep[v] = n.x != 0.0f || n.y != 0.0f || n.z != 0.0f;
        mesh->normals[v] = n;
        group[v] = (uint32_t)cs[v].v;
        all_kept = all_kept && keep[v];
    }
    memcpy(mesh->indices, r->indices.data, r->indices.count * sizeof(uint32_t));
    bool ok = all_kept || sl_scene_compute_normals(mesh, group, (uint32_t)r->positions.count, keep);
    ok = ok && sl_scene_compute_tangents(mesh); /* OBJ has no tangents: generated from vt */
    free(keep);
    free(group);
    if (!ok) {
        sl_mesh_free(mesh);
        return sl_fail(r->err, SL_ERR_MEMORY, "%s: out of memory", r->name);
    }
    return true;
}

/* ---- entry points: text and files ---- */

/* UTF-16 or UTF-32 text, named so that the user can save it as UTF-8, rather than the "NUL
 * byte" a byte-wise reader would report; NULL for anything else. Without a byte-order mark,
 * ASCII in UTF-16 shows as every other byte zero. */
static const char *wide_text(const unsigned char *b, size_t size)
{
    if (size >= 4 && b[0] == 0xFF && b[1] == 0xFE && b[2] == 0 && b[3] == 0)
        return "UTF-32 (little-endian, byte-order mark FF FE 00 00)";
    if (size >= 4 && b[0] == 0 && b[1] == 0 && b[2] == 0xFE && b[3] == 0xFF)
        return "UTF-32 (big-endian, byte-order mark 00 00 FE FF)";
    if (size >= 2 && b[0] == 0xFF && b[1] == 0xFE)
        return "UTF-16 (little-endian, byte-order mark FF FE)";
    if (size >= 2 && b[0] == 0xFE && b[1] == 0xFF)
        return "UTF-16 (big-endian, byte-order mark FE FF)";
    if (size >= 4 && b[0] && !b[1] && b[2] && !b[3])
        return "UTF-16 (little-endian, no byte-order mark)";
    if (size >= 4 && !b[0] && b[1] && !b[2] && b[3])
        return "UTF-16 (big-endian, no byte-order mark)";
    return NULL;
}

bool sl_mesh_parse_obj(const char *text, size_t size, const char *name, sl_mesh *mesh, sl_error *err)
{
    memset(mesh, 0, sizeof *mesh);
    if (!name)
        name = "obj";
    const char *wide = wide_text((const unsigned char *)text, size);
    if (wide)
        return sl_fail(err, SL_ERR_FORMAT, "%s:1: the file is %s, expected ASCII or UTF-8 text (save it as UTF-8)",
                       name, wide);
    /* A private NUL-terminated copy: lines are split and tokenised in place, and strtof
     * needs a terminator that memory from a fuzzer or a mapped file does not promise. */
    char *buf = malloc(size + 1);
    if (!buf)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for %zu bytes", name, size);
    if (size)
        memcpy(buf, text, size);
    buf[size] = '\0';

    obj_reader r = {.name = name, .err = err};
    r.positions.elem = sizeof(vec3);
    r.texcoords.elem = sizeof(vec2);
    r.normals.elem = sizeof(vec3);
    r.corners.elem = sizeof(corner);
    r.indices.elem = sizeof(uint32_t);
    r.face.elem = sizeof(corner);
    r.face_index.elem = sizeof(uint32_t);
    r.pending.elem = sizeof(corner);
    r.pending_faces.elem = sizeof(pending_face);

    bool ok = true;
    char *p = buf, *end = buf + size;
    if (size >= 3 && memcmp(buf, "\xef\xbb\xbf", 3) == 0)
        p += 3; /* a UTF-8 byte-order mark, as Windows editors write */
    size_t next_line = 1;
    while (ok && p < end) {
        /* One statement: a line ended by LF, CRLF or CR, joined with the next while it ends
         * in a backslash (the backslash and the line end become spaces). */
        r.line = next_line;
        char *line = p, *stop;
        for (;;) {
            stop = p;
            while (stop < end && *stop != '\n' && *stop != '\r')
                stop++;
            size_t term = stop == end ? 0 : (*stop == '\r' && stop + 1 < end && stop[1] == '\n') ? 2 : 1;
            next_line += term != 0;
            bool continued = stop > p && stop[-1] == '\\';
            if (continued)
                stop[-1] = ' ';
            p = stop + term;
            if (!continued || term == 0)
                break;
            memset(stop, ' ', term);
        }
        *stop = '\0';
        if (strlen(line) != (size_t)(stop - line))
            ok = fail_line(&r, SL_ERR_FORMAT, "NUL byte inside a line (not a text file?)", NULL);
        else
            ok = parse_line(&r, line);
    }
    size_t lines = next_line - 1 + (size > 0 && text[size - 1] != '\n' && text[size - 1] != '\r');
    if (ok)
        ok = build_pending(&r);
    if (ok && r.indices.count == 0)
        ok = sl_fail(err, SL_ERR_FORMAT, "%s: no faces (%zu lines, %zu positions)", name, lines, r.positions.count);
    if (ok)
        ok = build_mesh(&r, mesh);
    reader_free(&r);
    free(buf);
    return ok;
}

bool sl_mesh_load_obj(const char *path, sl_mesh *mesh, sl_error *err)
{
    memset(mesh, 0, sizeof *mesh);
    unsigned char *bytes;
    size_t size;
    if (!sl_read_file(path, OBJ_MAX_FILE_BYTES, &bytes, &size, err))
        return false;
    bool ok = sl_mesh_parse_obj((const char *)bytes, size, path, mesh, err);
    free(bytes);
    return ok;
}
