/* gltf_check.c - the checks softlight makes on a glTF 2.0 file before assimp reads it.
 *
 * Owns: the .glb container (header, lengths, the JSON chunk) and the JSON types of the glTF
 * fields that decide what arrives (node transforms and references, material factors,
 * accessors). assimp 5.2 reads a wrong type silently as the default ("scale": "big" becomes
 * 1) and a truncated .glb as "no suitable reader"; a user gets instead one line with the JSON
 * path, as the scene reader gives. Indices, buffer bounds and recursion are assimp's checks
 * and model.c's (the glTF importer refuses cycles; model.c caps the depth it walks). */
#include "scene_internal.h"

#include <cjson/cJSON.h>
#include <stdint.h>
#include <stdio.h>
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
    if (!cJSON_IsNumber(v) || v->valuedouble != (double)(int)v->valuedouble || v->valueint < 0)
        return bad(c, path, "a non-negative integer");
    if (count >= 0 && v->valueint >= count)
        return sl_fail(c->err, SL_ERR_FORMAT, "%s: %s: %d out of range (%d %s)", c->name, path, v->valueint, count,
                       of);
    return true;
}

static int count_of(const cJSON *root, const char *key)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(root, key);
    return cJSON_IsArray(a) ? cJSON_GetArraySize(a) : 0;
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

static bool check_json(checker *c, const char *json, size_t size)
{
    cJSON *root = cJSON_ParseWithLength(json, size);
    if (!root)
        return sl_fail(c->err, SL_ERR_FORMAT, "%s: invalid JSON in the glTF document", c->name);
    bool ok = cJSON_IsObject(root) || bad(c, "top level", "a JSON object");
    static const char *const arrays[] = {"scenes", "nodes", "meshes", "materials", "accessors", "bufferViews",
                                         "buffers", "images", "textures", "samplers", "cameras"};
    for (size_t i = 0; ok && i < sizeof arrays / sizeof arrays[0]; i++) {
        const cJSON *a = cJSON_GetObjectItemCaseSensitive(root, arrays[i]);
        if (!a)
            continue;
        ok = cJSON_IsArray(a) || bad(c, arrays[i], "an array of objects");
        int k = 0;
        for (const cJSON *e = ok ? a->child : NULL; ok && e; e = e->next, k++) {
            char path[64];
            snprintf(path, sizeof path, "%s[%d]", arrays[i], k);
            ok = cJSON_IsObject(e) || bad(c, path, "an object");
            if (ok && strcmp(arrays[i], "nodes") == 0)
                ok = check_node(c, e, path, count_of(root, "nodes"), count_of(root, "meshes"),
                                count_of(root, "cameras"));
            else if (ok && strcmp(arrays[i], "materials") == 0)
                ok = check_material(c, e, path, count_of(root, "textures"));
            else if (ok && strcmp(arrays[i], "textures") == 0)
                ok = check_texture(c, e, path, count_of(root, "images"), count_of(root, "samplers"));
            else if (ok && strcmp(arrays[i], "meshes") == 0)
                ok = check_mesh(c, e, path, count_of(root, "accessors"), count_of(root, "materials"));
            else if (ok && strcmp(arrays[i], "accessors") == 0)
                ok = check_accessor(c, e, path, count_of(root, "bufferViews"));
            else if (ok && strcmp(arrays[i], "images") == 0)
                ok = check_image(c, e, path, count_of(root, "bufferViews"));
        }
    }
    cJSON_Delete(root);
    return ok;
}

bool sl_scene_gltf_check(const unsigned char *bytes, size_t size, bool glb, const char *name, sl_error *err)
{
    checker c = {.name = name, .err = err};
    if (!glb)
        return check_json(&c, (const char *)bytes, size);
    if (size < 20 || le32(bytes) != GLB_MAGIC)
        return sl_fail(err, SL_ERR_FORMAT, "%s: not a .glb file (%s)", name,
                       size < 20 ? "shorter than its 20-byte header" : "no \"glTF\" magic at byte 0");
    uint32_t version = le32(bytes + 4), length = le32(bytes + 8), json_len = le32(bytes + 12);
    if (version != 2)
        return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: .glb version %u (softlight reads glTF 2.0)", name, version);
    if (length > size)
        return sl_fail(err, SL_ERR_FORMAT, "%s: truncated .glb: its header says %u bytes, the file has %zu", name,
                       length, size);
    if (le32(bytes + 16) != GLB_JSON || json_len > length - 20)
        return sl_fail(err, SL_ERR_FORMAT, "%s: .glb's first chunk is not a JSON chunk within the file", name);
    return check_json(&c, (const char *)bytes + 20, json_len);
}
