/* gltf_check.c - the checks softlight makes on a glTF 2.0 file before assimp reads it.
 *
 * Owns: the .glb container (header, lengths, the JSON chunk) and the JSON types of the glTF
 * fields that decide what arrives (node transforms and references, material factors,
 * accessors). assimp 5.2 reads a wrong type silently as the default ("scale": "big" becomes
 * 1) and a truncated .glb as "no suitable reader"; a user gets instead one line with the JSON
 * path, as the scene reader gives. The document's sizes are capped before anything else, and
 * the node graph (trees, depth, instances) is checked in linear time before the importer, whose
 * recursion would overflow the stack on a deep chain. Buffer bounds are assimp's checks. */
#include "model.h"
#include "scene_internal.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GLB_MAGIC 0x46546C67u /* "glTF" */
#define GLB_JSON 0x4E4F534Au  /* "JSON" */

typedef struct {
    const char *name;
    sl_error *err;
} checker;

static uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static bool bad(checker *c, const char *path, const char *what)
{
    return sl_fail(c->err, SL_ERR_FORMAT, "%s: %s: expected %s", c->name, path, what);
}

/* An array of n numbers (n = 0: any length). */
static bool numbers(checker *c, const cJSON *v, const char *path, int n)
{
    char what[40];
    snprintf(what, sizeof what, n ? "an array of %d numbers" : "an array of numbers", n);
    if (!cJSON_IsArray(v) || (n && cJSON_GetArraySize(v) != n))
        return bad(c, path, what);
    for (const cJSON *e = v->child; e; e = e->next)
        if (!cJSON_IsNumber(e))
            return bad(c, path, what);
    return true;
}

/* A non-negative integer below `count` (count < 0: no upper bound). */
static bool index_in(checker *c, const cJSON *v, const char *path, int count, const char *of)
{
    if (!cJSON_IsNumber(v) || !(v->valuedouble >= 0.0) || v->valuedouble != floor(v->valuedouble))
        return bad(c, path, "a non-negative integer");
    if (v->valuedouble > (double)INT32_MAX)
        return sl_fail(c->err, SL_ERR_RANGE, "%s: %s: %.0f is too large (at most %d)", c->name, path, v->valuedouble,
                       INT32_MAX);
    if (count >= 0 && v->valueint >= count)
        return sl_fail(c->err, SL_ERR_FORMAT, "%s: %s: %d out of range (%d %s)", c->name, path, v->valueint, count,
                       of);
    return true;
}

static bool check_node(checker *c, const cJSON *n, const char *path, int nodes, int meshes, int cameras)
{
    char sub[96];
    const cJSON *v;
    static const struct {
        const char *key;
        int n;
    } vectors[] = {{"matrix", 16}, {"translation", 3}, {"rotation", 4}, {"scale", 3}};
    for (size_t i = 0; i < sizeof vectors / sizeof vectors[0]; i++) {
        snprintf(sub, sizeof sub, "%s.%s", path, vectors[i].key);
        if ((v = cJSON_GetObjectItemCaseSensitive(n, vectors[i].key)) && !numbers(c, v, sub, vectors[i].n))
            return false;
    }
    snprintf(sub, sizeof sub, "%s.mesh", path);
    if ((v = cJSON_GetObjectItemCaseSensitive(n, "mesh")) && !index_in(c, v, sub, meshes, "meshes"))
        return false;
    snprintf(sub, sizeof sub, "%s.camera", path);
    if ((v = cJSON_GetObjectItemCaseSensitive(n, "camera")) && !index_in(c, v, sub, cameras, "cameras"))
        return false;
    snprintf(sub, sizeof sub, "%s.children", path);
    if ((v = cJSON_GetObjectItemCaseSensitive(n, "children"))) {
        if (!cJSON_IsArray(v))
            return bad(c, sub, "an array of node indices");
        int i = 0;
        for (const cJSON *e = v->child; e; e = e->next, i++) {
            char el[112];
            snprintf(el, sizeof el, "%s[%d]", sub, i);
            if (!index_in(c, e, el, nodes, "nodes"))
                return false;
        }
    }
    return true;
}

/* A textureInfo ({"index": N, "texCoord": K, ...}): assimp 5.2's glTF importer crashes on one
 * without "index" (found by fuzz_model). */
static bool check_texture_info(checker *c, const cJSON *parent, const char *key, const char *path, int textures)
{
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(parent, key), *v;
    if (!t)
        return true;
    char sub[160];
    snprintf(sub, sizeof sub, "%s.%s", path, key);
    if (!cJSON_IsObject(t))
        return bad(c, sub, "an object {\"index\": ...}");
    snprintf(sub, sizeof sub, "%s.%s.index", path, key);
    if (!(v = cJSON_GetObjectItemCaseSensitive(t, "index")))
        return bad(c, sub, "a texture index");
    if (!index_in(c, v, sub, textures, "textures"))
        return false;
    snprintf(sub, sizeof sub, "%s.%s.texCoord", path, key);
    return !(v = cJSON_GetObjectItemCaseSensitive(t, "texCoord")) || index_in(c, v, sub, 8, "UV sets at most");
}

static bool check_material(checker *c, const cJSON *m, const char *path, int textures)
{
    char sub[128];
    const cJSON *pbr = cJSON_GetObjectItemCaseSensitive(m, "pbrMetallicRoughness"), *v;
    static const char *const maps[] = {"normalTexture", "occlusionTexture", "emissiveTexture"};
    for (int i = 0; i < 3; i++)
        if (!check_texture_info(c, m, maps[i], path, textures))
            return false;
    if (pbr) {
        snprintf(sub, sizeof sub, "%s.pbrMetallicRoughness", path);
        if (!cJSON_IsObject(pbr))
            return bad(c, sub, "an object");
        snprintf(sub, sizeof sub, "%s.pbrMetallicRoughness", path);
        if (!check_texture_info(c, pbr, "baseColorTexture", sub, textures) ||
            !check_texture_info(c, pbr, "metallicRoughnessTexture", sub, textures))
            return false;
        snprintf(sub, sizeof sub, "%s.pbrMetallicRoughness.baseColorFactor", path);
        if ((v = cJSON_GetObjectItemCaseSensitive(pbr, "baseColorFactor")) && !numbers(c, v, sub, 4))
            return false;
        static const char *const factors[] = {"metallicFactor", "roughnessFactor"};
        for (int i = 0; i < 2; i++) {
            snprintf(sub, sizeof sub, "%s.pbrMetallicRoughness.%s", path, factors[i]);
            if ((v = cJSON_GetObjectItemCaseSensitive(pbr, factors[i])) && !cJSON_IsNumber(v))
                return bad(c, sub, "a number");
        }
    }
    snprintf(sub, sizeof sub, "%s.emissiveFactor", path);
    if ((v = cJSON_GetObjectItemCaseSensitive(m, "emissiveFactor")) && !numbers(c, v, sub, 3))
        return false;
    snprintf(sub, sizeof sub, "%s.alphaMode", path);
    if ((v = cJSON_GetObjectItemCaseSensitive(m, "alphaMode")) &&
        (!cJSON_IsString(v) || (strcmp(v->valuestring, "OPAQUE") && strcmp(v->valuestring, "MASK") &&
                                strcmp(v->valuestring, "BLEND"))))
        return bad(c, sub, "\"OPAQUE\", \"MASK\" or \"BLEND\"");
    snprintf(sub, sizeof sub, "%s.alphaCutoff", path);
    if ((v = cJSON_GetObjectItemCaseSensitive(m, "alphaCutoff")) && !cJSON_IsNumber(v))
        return bad(c, sub, "a number");
    snprintf(sub, sizeof sub, "%s.doubleSided", path);
    if ((v = cJSON_GetObjectItemCaseSensitive(m, "doubleSided")) && !cJSON_IsBool(v))
        return bad(c, sub, "true or false");
    return true;
}

static bool check_accessor(checker *c, const cJSON *a, const char *path, int views)
{
    char sub[96];
    const cJSON *v;
    snprintf(sub, sizeof sub, "%s.count", path);
    if (!(v = cJSON_GetObjectItemCaseSensitive(a, "count")) || !index_in(c, v, sub, -1, ""))
        return v ? false : bad(c, sub, "a non-negative integer");
    snprintf(sub, sizeof sub, "%s.componentType", path);
    if (!(v = cJSON_GetObjectItemCaseSensitive(a, "componentType")) || !index_in(c, v, sub, -1, ""))
        return v ? false : bad(c, sub, "a component type (5120..5126)");
    snprintf(sub, sizeof sub, "%s.type", path);
    if (!(v = cJSON_GetObjectItemCaseSensitive(a, "type")) || !cJSON_IsString(v))
        return bad(c, sub, "a string (\"SCALAR\", \"VEC3\", ...)");
    snprintf(sub, sizeof sub, "%s.bufferView", path);
    if ((v = cJSON_GetObjectItemCaseSensitive(a, "bufferView")) && !index_in(c, v, sub, views, "bufferViews"))
        return false;
    return true;
}

static bool check_texture(checker *c, const cJSON *t, const char *path, int images, int samplers)
{
    char sub[96];
    const cJSON *v;
    snprintf(sub, sizeof sub, "%s.source", path);
    if ((v = cJSON_GetObjectItemCaseSensitive(t, "source")) && !index_in(c, v, sub, images, "images"))
        return false;
    snprintf(sub, sizeof sub, "%s.sampler", path);
    return !(v = cJSON_GetObjectItemCaseSensitive(t, "sampler")) || index_in(c, v, sub, samplers, "samplers");
}

/* An image: a uri string or a bufferView in range, and a mimeType glTF 2.0 allows. assimp 5.2
 * takes the text after the mimeType's '/' without checking there is one (a NULL + 1 pointer:
 * found by fuzz_model). */
static bool check_image(checker *c, const cJSON *im, const char *path, int views)
{
    char sub[96];
    const cJSON *v;
    snprintf(sub, sizeof sub, "%s.mimeType", path);
    if ((v = cJSON_GetObjectItemCaseSensitive(im, "mimeType")) &&
        !(cJSON_IsString(v) && (!strcmp(v->valuestring, "image/png") || !strcmp(v->valuestring, "image/jpeg"))))
        return bad(c, sub, "\"image/png\" or \"image/jpeg\"");
    snprintf(sub, sizeof sub, "%s.uri", path);
    if ((v = cJSON_GetObjectItemCaseSensitive(im, "uri")) && !cJSON_IsString(v))
        return bad(c, sub, "a string");
    snprintf(sub, sizeof sub, "%s.bufferView", path);
    return !(v = cJSON_GetObjectItemCaseSensitive(im, "bufferView")) || index_in(c, v, sub, views, "bufferViews");
}

/* primitives: an array of objects whose attributes, indices and material are in range. */
static bool check_mesh(checker *c, const cJSON *m, const char *path, int accessors, int materials)
{
    char sub[160];
    const cJSON *prims = cJSON_GetObjectItemCaseSensitive(m, "primitives"), *v;
    snprintf(sub, sizeof sub, "%s.primitives", path);
    if (!cJSON_IsArray(prims))
        return bad(c, sub, "an array of primitives");
    int i = 0;
    for (const cJSON *p = prims->child; p; p = p->next, i++) {
        snprintf(sub, sizeof sub, "%s.primitives[%d]", path, i);
        if (!cJSON_IsObject(p))
            return bad(c, sub, "an object");
        const cJSON *attrs = cJSON_GetObjectItemCaseSensitive(p, "attributes");
        snprintf(sub, sizeof sub, "%s.primitives[%d].attributes", path, i);
        if (!cJSON_IsObject(attrs))
            return bad(c, sub, "an object {\"POSITION\": ...}");
        for (const cJSON *a = attrs->child; a; a = a->next) {
            char el[224];
            snprintf(el, sizeof el, "%s.%.48s", sub, a->string);
            if (!index_in(c, a, el, accessors, "accessors"))
                return false;
        }
        snprintf(sub, sizeof sub, "%s.primitives[%d].indices", path, i);
        if ((v = cJSON_GetObjectItemCaseSensitive(p, "indices")) && !index_in(c, v, sub, accessors, "accessors"))
            return false;
        snprintf(sub, sizeof sub, "%s.primitives[%d].material", path, i);
        if ((v = cJSON_GetObjectItemCaseSensitive(p, "material")) && !index_in(c, v, sub, materials, "materials"))
            return false;
    }
    return true;
}

/* The document's top-level arrays, each counted once: cJSON_GetArraySize walks a list, so
 * counting per element would make the checks quadratic in the file's size. */
enum { A_SCENES, A_NODES, A_MESHES, A_MATERIALS, A_ACCESSORS, A_VIEWS, A_BUFFERS, A_IMAGES, A_TEXTURES,
       A_SAMPLERS, A_CAMERAS, A_COUNT };
static const char *const array_names[A_COUNT] = {"scenes",      "nodes",   "meshes", "materials",
                                                 "accessors",   "bufferViews", "buffers", "images",
                                                 "textures",    "samplers", "cameras"};

/* The caps of model.h, applied to the document before any element is checked and before the
 * importer builds anything: a 2 MB file can list 200,000 nodes, and the importer's own limits
 * come only after its allocations. */
static bool within_caps(checker *c, const int count[A_COUNT])
{
    static const struct {
        int array, cap;
    } caps[] = {{A_NODES, SL_MODEL_MAX_NODES},
                {A_MESHES, SL_MODEL_MAX_MESHES},
                {A_MATERIALS, SL_MODEL_MAX_MATERIALS},
                {A_IMAGES, SL_MODEL_MAX_IMAGES},
                {A_TEXTURES, SL_MODEL_MAX_IMAGES}};
    for (size_t i = 0; i < sizeof caps / sizeof caps[0]; i++)
        if (count[caps[i].array] > caps[i].cap)
            return sl_fail(c->err, SL_ERR_RANGE, "%s: %d %s (softlight reads at most %d)", c->name,
                           count[caps[i].array], array_names[caps[i].array], caps[i].cap);
    return true;
}

/* The node graph, once every node passed check_node (children are in-range indices): glTF's nodes
 * form disjoint trees, so each node has at most one parent; the depth is capped, and so is the
 * number of mesh instances the trees make (a node holding mesh m makes one per primitive of m).
 * All in time linear in the nodes, before the importer recurses down a 20,000-deep chain. */
static bool check_hierarchy(checker *c, const cJSON *nodes, int node_count, const cJSON *meshes, int mesh_count)
{
    if (node_count == 0)
        return true;
    int *parent = malloc((size_t)node_count * sizeof *parent);
    int *depth = malloc((size_t)node_count * sizeof *depth);
    int *queue = malloc((size_t)node_count * sizeof *queue);
    int *prims = malloc((size_t)(mesh_count ? mesh_count : 1) * sizeof *prims);
    const cJSON **node = malloc((size_t)node_count * sizeof *node);
    bool ok = parent && depth && queue && prims && node;
    if (!ok)
        sl_fail(c->err, SL_ERR_MEMORY, "%s: out of memory for the node graph", c->name);
    int m = 0;
    for (const cJSON *e = ok && meshes ? meshes->child : NULL; e; e = e->next, m++) {
        const cJSON *p = cJSON_GetObjectItemCaseSensitive(e, "primitives");
        int n = 0;
        for (const cJSON *q = p ? p->child : NULL; q; q = q->next)
            n++;
        prims[m] = n;
    }
    int k = 0;
    long instances = 0;
    for (const cJSON *e = ok ? nodes->child : NULL; e; e = e->next, k++) {
        node[k] = e;
        parent[k] = -1;
        depth[k] = -1;
        const cJSON *mesh = cJSON_GetObjectItemCaseSensitive(e, "mesh");
        if (mesh)
            instances += prims[mesh->valueint];
    }
    if (ok && instances > SL_MODEL_MAX_INSTANCES)
        ok = sl_fail(c->err, SL_ERR_RANGE, "%s: its nodes place %ld mesh instances (softlight draws at most %d)",
                     c->name, instances, SL_MODEL_MAX_INSTANCES);
    for (k = 0; ok && k < node_count; k++) {
        const cJSON *children = cJSON_GetObjectItemCaseSensitive(node[k], "children");
        for (const cJSON *e = children ? children->child : NULL; ok && e; e = e->next) {
            int child = e->valueint;
            if (child == k || parent[child] >= 0)
                ok = sl_fail(c->err, SL_ERR_FORMAT,
                             child == k ? "%s: nodes[%d] is its own child (recursive nodes)"
                                        : "%s: nodes[%d] has two parents, nodes[%d] and nodes[%d] (glTF nodes form trees)",
                             c->name, child, parent[child], k);
            else
                parent[child] = k;
        }
    }
    /* Breadth first from the roots: a node no root reaches lies on a cycle or below one. */
    int head = 0, tail = 0;
    for (k = 0; ok && k < node_count; k++)
        if (parent[k] < 0) {
            depth[k] = 0;
            queue[tail++] = k;
        }
    while (ok && head < tail) {
        int n = queue[head++];
        if (depth[n] >= SL_MODEL_MAX_NODE_DEPTH) {
            ok = sl_fail(c->err, SL_ERR_RANGE, "%s: nodes nested deeper than %d levels (nodes[%d])", c->name,
                         SL_MODEL_MAX_NODE_DEPTH, n);
            break;
        }
        const cJSON *children = cJSON_GetObjectItemCaseSensitive(node[n], "children");
        for (const cJSON *e = children ? children->child : NULL; e; e = e->next) {
            depth[e->valueint] = depth[n] + 1;
            queue[tail++] = e->valueint;
        }
    }
    for (k = 0; ok && k < node_count; k++)
        if (depth[k] < 0)
            ok = sl_fail(c->err, SL_ERR_FORMAT, "%s: nodes[%d] is its own ancestor (recursive nodes)", c->name, k);
    free(parent);
    free(depth);
    free(queue);
    free(prims);
    free(node);
    return ok;
}

/* Every number of the document is finite: the JSON parser reads 1e999 as infinity, which the
 * importer would take for a coordinate or a count. `path` names the value (built as the walk goes
 * down, cut short past its buffer). */
static bool all_finite(checker *c, const cJSON *v, char *path, size_t len, size_t cap)
{
    if (cJSON_IsNumber(v) && !isfinite(v->valuedouble))
        return sl_fail(c->err, SL_ERR_RANGE, "%s: %s: a number out of range (not a finite double)", c->name,
                       len ? path : "top level");
    int i = 0;
    for (const cJSON *e = v->child; e; e = e->next, i++) {
        int n = e->string ? snprintf(path + len, cap - len, "%s%.32s", len ? "." : "", e->string)
                          : snprintf(path + len, cap - len, "[%d]", i);
        size_t sub = n < 0 || (size_t)n >= cap - len ? len : len + (size_t)n;
        if (!all_finite(c, e, path, sub, cap))
            return false;
        path[len] = '\0';
    }
    return true;
}

/* The version (glTF 1.0 files have another layout, which the checks below would misread) and
 * the required extensions: the glTF specification has a loader refuse a file that requires
 * an extension it does not implement, rather than draw it wrongly. softlight implements
 * KHR_texture_transform (without rotation). */
static bool check_asset(checker *c, const cJSON *root)
{
    const cJSON *asset = cJSON_GetObjectItemCaseSensitive(root, "asset");
    const cJSON *version = cJSON_GetObjectItemCaseSensitive(asset, "version");
    if (cJSON_IsString(version) && strncmp(version->valuestring, "2.", 2) != 0) {
        char shown[24];
        return sl_fail(c->err, SL_ERR_UNSUPPORTED, "%s: glTF version \"%s\" (softlight reads glTF 2.0)", c->name,
                       sl_error_excerpt(version->valuestring, 16, shown, sizeof shown));
    }
    /* glTF 1.0 as its early exporters wrote it: "version": 1, a number (collada2gltf), or no
     * version and its layout, objects keyed by id where 2.0 has arrays ("scenes": {...}). */
    if (cJSON_IsNumber(version) && version->valuedouble != 2.0)
        return sl_fail(c->err, SL_ERR_UNSUPPORTED, "%s: glTF version %g (softlight reads glTF 2.0)", c->name,
                       version->valuedouble);
    static const char *const arrays[] = {"scenes", "nodes", "meshes", "accessors", "bufferViews", "buffers"};
    for (size_t i = 0; !cJSON_IsString(version) && i < sizeof arrays / sizeof arrays[0]; i++)
        if (cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(root, arrays[i])))
            return sl_fail(c->err, SL_ERR_UNSUPPORTED, "%s: \"%s\" is an object keyed by id: glTF 1.0's layout "
                           "(softlight reads glTF 2.0, whose \"%s\" is an array)", c->name, arrays[i], arrays[i]);
    const cJSON *required = cJSON_GetObjectItemCaseSensitive(root, "extensionsRequired");
    if (required && !cJSON_IsArray(required))
        return bad(c, "extensionsRequired", "an array of extension names");
    for (const cJSON *e = required ? required->child : NULL; e; e = e->next) {
        char shown[72];
        if (!cJSON_IsString(e))
            return bad(c, "extensionsRequired", "an array of extension names");
        if (strcmp(e->valuestring, "KHR_texture_transform") == 0)
            continue; /* model.c applies it (a rotation is refused there) */
        return sl_fail(c->err, SL_ERR_UNSUPPORTED, "%s: requires the glTF extension %s, which softlight does not implement",
                       c->name, sl_error_excerpt(e->valuestring, 64, shown, sizeof shown));
    }
    return true;
}

/* The triangles the meshes declare, for the import to be checked against (assimp drops a
 * triangle with an index out of range, with a log line nobody sees): -1 when a primitive is not
 * a triangle list (strips and fans are converted by the importer and not counted). Refuses a
 * triangle list whose index (or vertex) count is not a multiple of 3. */
static bool count_triangles(checker *c, const cJSON *meshes, const cJSON *accessors, int accessor_count,
                            long long *triangles)
{
    *triangles = 0;
    if (!meshes)
        return true;
    long long *counts = malloc((size_t)(accessor_count ? accessor_count : 1) * sizeof *counts);
    if (!counts)
        return sl_fail(c->err, SL_ERR_MEMORY, "%s: out of memory for the accessors", c->name);
    int a = 0;
    for (const cJSON *e = accessors ? accessors->child : NULL; e; e = e->next, a++)
        counts[a] = (long long)cJSON_GetObjectItemCaseSensitive(e, "count")->valuedouble;
    bool ok = true;
    int m = 0;
    for (const cJSON *mesh = meshes->child; ok && mesh; mesh = mesh->next, m++) {
        int p = 0;
        const cJSON *prims = cJSON_GetObjectItemCaseSensitive(mesh, "primitives");
        for (const cJSON *prim = prims->child; ok && prim; prim = prim->next, p++) {
            const cJSON *mode = cJSON_GetObjectItemCaseSensitive(prim, "mode");
            const cJSON *indices = cJSON_GetObjectItemCaseSensitive(prim, "indices");
            const cJSON *position =
                cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(prim, "attributes"), "POSITION");
            if (mode && !(cJSON_IsNumber(mode) && mode->valuedouble == 4.0)) {
                *triangles = -1; /* points, lines, strips, fans */
                continue;
            }
            if (!indices && !position)
                continue; /* the importer refuses it with its own message */
            long long n = counts[(indices ? indices : position)->valueint];
            if (n % 3 != 0)
                ok = sl_fail(c->err, SL_ERR_FORMAT, "%s: meshes[%d].primitives[%d]: %lld %s, not a multiple of 3 for "
                             "a triangle list", c->name, m, p, n, indices ? "indices" : "vertices");
            else if (*triangles >= 0)
                *triangles += n / 3;
        }
    }
    free(counts);
    return ok;
}

static bool check_json(checker *c, const char *json, size_t size, scene_gltf_facts *facts)
{
    cJSON *root = cJSON_ParseWithLength(json, size);
    if (!root)
        return sl_fail(c->err, SL_ERR_FORMAT, "%s: invalid JSON in the glTF document", c->name);
    char where[256] = "";
    bool ok = (cJSON_IsObject(root) || bad(c, "top level", "a JSON object")) && check_asset(c, root) &&
              all_finite(c, root, where, 0, sizeof where);
    const cJSON *array[A_COUNT] = {0};
    int count[A_COUNT] = {0};
    for (int i = 0; ok && i < A_COUNT; i++) {
        array[i] = cJSON_GetObjectItemCaseSensitive(root, array_names[i]);
        ok = !array[i] || cJSON_IsArray(array[i]) || bad(c, array_names[i], "an array of objects");
        if (ok && array[i])
            count[i] = cJSON_GetArraySize(array[i]);
    }
    ok = ok && within_caps(c, count);
    for (int i = 0; ok && i < A_COUNT; i++) {
        int k = 0;
        for (const cJSON *e = array[i] ? array[i]->child : NULL; ok && e; e = e->next, k++) {
            char path[64];
            snprintf(path, sizeof path, "%s[%d]", array_names[i], k);
            ok = cJSON_IsObject(e) || bad(c, path, "an object");
            if (!ok)
                break;
            switch (i) {
            case A_NODES: ok = check_node(c, e, path, count[A_NODES], count[A_MESHES], count[A_CAMERAS]); break;
            case A_MATERIALS: ok = check_material(c, e, path, count[A_TEXTURES]); break;
            case A_TEXTURES: ok = check_texture(c, e, path, count[A_IMAGES], count[A_SAMPLERS]); break;
            case A_MESHES: ok = check_mesh(c, e, path, count[A_ACCESSORS], count[A_MATERIALS]); break;
            case A_ACCESSORS: ok = check_accessor(c, e, path, count[A_VIEWS]); break;
            case A_IMAGES: ok = check_image(c, e, path, count[A_VIEWS]); break;
            default: break;
            }
        }
    }
    ok = ok && check_hierarchy(c, array[A_NODES], count[A_NODES], array[A_MESHES], count[A_MESHES]);
    ok = ok && count_triangles(c, array[A_MESHES], array[A_ACCESSORS], count[A_ACCESSORS], &facts->triangles);
    for (const cJSON *b = ok && array[A_BUFFERS] ? array[A_BUFFERS]->child : NULL; b; b = b->next) {
        const cJSON *length = cJSON_GetObjectItemCaseSensitive(b, "byteLength");
        if (cJSON_IsNumber(length) && length->valuedouble > 0)
            facts->buffer_bytes += length->valuedouble < (double)SL_MODEL_MAX_FILE_BYTES ? (size_t)length->valuedouble
                                                                                       : SL_MODEL_MAX_FILE_BYTES;
    }
    cJSON_Delete(root);
    return ok;
}

bool sl_scene_gltf_check(const unsigned char *bytes, size_t size, bool glb, const char *name, scene_gltf_facts *facts,
                      sl_error *err)
{
    checker c = {.name = name, .err = err};
    scene_gltf_facts ignored;
    if (!facts)
        facts = &ignored;
    *facts = (scene_gltf_facts){0};
    if (!glb)
        return check_json(&c, (const char *)bytes, size, facts);
    if (size < 20 || le32(bytes) != GLB_MAGIC)
        return sl_fail(err, SL_ERR_FORMAT, "%s: not a .glb file (%s)", name,
                       size < 20 ? "shorter than its 20-byte header" : "no \"glTF\" magic at byte 0");
    uint32_t version = le32(bytes + 4), length = le32(bytes + 8), json_len = le32(bytes + 12);
    if (version != 2)
        return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: .glb version %u (softlight reads glTF 2.0)", name, version);
    if (length != size)
        return sl_fail(err, SL_ERR_FORMAT, "%s: %s .glb: its header says %u bytes, the file has %zu", name,
                       length > size ? "truncated" : "damaged", length, size);
    if (le32(bytes + 16) != GLB_JSON || json_len > length - 20)
        return sl_fail(err, SL_ERR_FORMAT, "%s: .glb's first chunk is not a JSON chunk within the file", name);
    return check_json(&c, (const char *)bytes + 20, json_len, facts);
}
