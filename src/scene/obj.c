/* obj.c - Wavefront OBJ reader: the subset that describes one triangle mesh.
 *
 * Reads v, vt, vn and f (forms v, v/t, v//n, v/t/n; negative indices count back from the
 * last element defined so far); polygons are fan-triangulated (0, i, i+1). Comments and
 * statements that carry no geometry for softlight (o, g, s, usemtl, mtllib, l, p, and
 * anything unknown) are skipped. Indices must refer to elements defined earlier in the
 * file, which keeps the reader single-pass and the error message exact.
 *
 * Output: an indexed sl_mesh with one vertex per distinct (v, vt, vn) triple in order of
 * first use. Normals from the file are normalised; corners without one (or with a zero one)
 * get an angle-weighted normal accumulated per OBJ position, so a texture seam does not split
 * the shading. Errors carry `name:line:`; sizes are capped (scene_internal.h). */
#include "scene_internal.h"

#include "../core/image.h" /* sl_read_file */

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define OBJ_MAX_FILE_BYTES ((size_t)1 << 30)

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

/* One output vertex: 0-based indices into the file's v, vt, vn lists; -1 = absent. */
typedef struct {
    int32_t v, t, n;
} corner;

/* Open-addressing map from corner to output vertex index, kept under half full. */
typedef struct {
    uint32_t *slots; /* vertex index + 1; 0 = empty */
    size_t mask;
} corner_map;

typedef struct {
    const char *name;
    size_t line;
    sl_error *err;
    array positions, texcoords, normals; /* vec3, vec2, vec3 as read */
    array corners;                       /* corner, one per output vertex */
    array indices;                       /* uint32_t, 3 per triangle */
    corner_map map;
    bool any_texcoord;
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
            char detail[64];
            snprintf(detail, sizeof detail, "'%.32s'", tok);
            return fail_line(r, SL_ERR_FORMAT, "expected a number, got ", detail);
        }
        if (!isfinite(x)) {
            char detail[64];
            snprintf(detail, sizeof detail, " ('%.32s')", tok);
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

/* Resolve one OBJ index (1-based, or negative = relative to `count`) to 0-based. */
static bool resolve_index(obj_reader *r, const char *text, const char *kind, size_t count, int32_t *out)
{
    char *end;
    errno = 0;
    long i = strtol(text, &end, 10);
    if (end == text || *end) {
        char detail[96];
        snprintf(detail, sizeof detail, "%s index: expected an integer, got '%.32s'", kind, text);
        return fail_line(r, SL_ERR_FORMAT, detail, NULL);
    }
    long resolved = i > 0 ? i - 1 : (long)count + i;
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

/* Parse one face vertex: v, v/t, v//n or v/t/n. */
static bool parse_corner(obj_reader *r, char *tok, corner *c)
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
        char detail[64];
        snprintf(detail, sizeof detail, "'%.32s'", tok);
        return fail_line(r, SL_ERR_FORMAT, "malformed face vertex ", detail);
    }
    if (!resolve_index(r, parts[0], "face", r->positions.count, &c->v))
        return false;
    if (n >= 2 && parts[1][0]) {
        if (!resolve_index(r, parts[1], "texture coordinate", r->texcoords.count, &c->t))
            return false;
        r->any_texcoord = true;
    }
    if (n == 3) {
        if (!parts[2][0])
            return fail_line(r, SL_ERR_FORMAT, "malformed face vertex: empty normal index after '/'", NULL);
        if (!resolve_index(r, parts[2], "normal", r->normals.count, &c->n))
            return false;
    } else if (n == 2 && !parts[1][0]) {
        return fail_line(r, SL_ERR_FORMAT, "malformed face vertex: empty texture coordinate index after '/'",
                         NULL);
    }
    return true;
}

static bool parse_face(obj_reader *r, char *cursor)
{
    uint32_t first = 0, prev = 0;
    int n = 0;
    char *tok;
    while ((tok = next_token(&cursor)) != NULL) {
        corner c;
        uint32_t index = 0;
        if (!parse_corner(r, tok, &c) || !vertex_for(r, c, &index))
            return false;
        if (n == 0) {
            first = index;
        } else if (n >= 2) {
            if (r->indices.count / 3 >= SCENE_MAX_TRIANGLES) {
                char detail[64];
                snprintf(detail, sizeof detail, " (%d)", SCENE_MAX_TRIANGLES);
                return fail_line(r, SL_ERR_RANGE, "too many triangles", detail);
            }
            uint32_t tri[3] = {first, prev, index};
            for (int k = 0; k < 3; k++)
                if (!array_push(&r->indices, &tri[k]))
                    return fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
        }
        prev = index;
        n++;
    }
    if (n < 3) {
        char detail[64];
        snprintf(detail, sizeof detail, "a face needs at least 3 vertices, got %d", n);
        return fail_line(r, SL_ERR_FORMAT, detail, NULL);
    }
    return true;
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
        if (!scene_safe_normalize(n, &n))
            n = vec3s(0.0f);
        return array_push(&r->normals, &n) || fail_line(r, SL_ERR_MEMORY, "out of memory", NULL);
    }
    if (strcmp(keyword, "f") == 0)
        return parse_face(r, cursor);
    return true; /* o, g, s, usemtl, mtllib, l, p and unknown statements carry nothing we use */
}

static void reader_free(obj_reader *r)
{
    free(r->positions.data);
    free(r->texcoords.data);
    free(r->normals.data);
    free(r->corners.data);
    free(r->indices.data);
    free(r->map.slots);
}

/* Turn the parsed lists into the output mesh. */
static bool build_mesh(obj_reader *r, sl_mesh *mesh)
{
    int nv = (int)r->corners.count, nt = (int)(r->indices.count / 3);
    if (!scene_mesh_alloc(mesh, nv, nt, r->any_texcoord, r->name, r->err))
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
    bool ok = all_kept || scene_compute_normals(mesh, group, (uint32_t)r->positions.count, keep);
    free(keep);
    free(group);
    if (!ok) {
        sl_mesh_free(mesh);
        return sl_fail(r->err, SL_ERR_MEMORY, "%s: out of memory", r->name);
    }
    return true;
}

bool sl_mesh_parse_obj(const char *text, size_t size, const char *name, sl_mesh *mesh, sl_error *err)
{
    memset(mesh, 0, sizeof *mesh);
    if (!name)
        name = "obj";
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

    bool ok = true;
    char *p = buf, *end = buf + size;
    while (ok && p < end) {
        r.line++;
        char *nl = memchr(p, '\n', (size_t)(end - p));
        char *stop = nl ? nl : end;
        *stop = '\0';
        if (strlen(p) != (size_t)(stop - p))
            ok = fail_line(&r, SL_ERR_FORMAT, "NUL byte inside a line (not a text file?)", NULL);
        else
            ok = parse_line(&r, p);
        p = stop + 1;
    }
    if (ok && r.indices.count == 0)
        ok = sl_fail(err, SL_ERR_FORMAT, "%s: no faces (%zu lines, %zu positions)", name, r.line,
                     r.positions.count);
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
