/* model.c - model files through Debian's assimp (C API) into an sl_model (model.h).
 *
 * Owns: the import flags, the file access assimp gets, and the translation of assimp's scene
 * (meshes, node tree, materials, embedded textures, first camera) into softlight's types,
 * checked on the way: a model is input from elsewhere, so every count, index, float and
 * recursion is bounded here and not trusted to the importer.
 *
 * Import flags, and why each:
 * - ValidateDataStructure: assimp's own consistency check of what its importer built
 *   (indices in range, material indices, node references) before any post-process reads it.
 * - Triangulate, SortByPType with points and lines removed: the rasterizer draws triangles.
 * - JoinIdenticalVertices: OBJ and other face-corner formats come unindexed; shared vertices
 *   are what the vertex stage wants (3x fewer for a closed mesh).
 * - GenSmoothNormals: normals where the file has none ("generated smooth"); it
 *   leaves a file's own normals alone.
 * - CalcTangentSpace: tangents from the UVs where the file has none (normal maps need them);
 *   a glTF's TANGENT attribute is kept.
 * - FlipUVs: assimp turns every format's UVs into OpenGL's (v = 0 at the image's last row);
 *   flipping back gives glTF's convention for every format: v = 0 at the first row stored,
 *   which is how images are loaded (top row first).
 * Not used: PreTransformVertices (instances keep their node transforms), FindDegenerates and
 * FindInvalidData (they change topology; the rasterizer skips degenerate triangles and the
 * checks below refuse NaN), OptimizeMeshes/Graph (time spent for nothing the renderer needs).
 *
 * File access goes through an aiFileIO of ours: only regular files under the size cap are
 * opened (a .gltf naming /dev/zero or a FIFO as its buffer cannot hang the import), and the
 * file that could not be opened is remembered for the message ("missing model.bin"). A model
 * imported from memory sees only itself. */
#include "model.h"

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/GltfMaterial.h> /* AI_MATKEY_GLTF_ALPHAMODE, _ALPHACUTOFF */
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "scene_internal.h"

#define IMPORT_FLAGS                                                                                          \
    (aiProcess_ValidateDataStructure | aiProcess_Triangulate | aiProcess_SortByPType |                        \
     aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals | aiProcess_CalcTangentSpace |               \
     aiProcess_FlipUVs)

/* ---- file access for assimp: whole files in memory, regular files only ---- */

typedef struct {
    const char *name; /* the model as given (messages) */
    bool gltf;        /* a glTF file (.gltf, .glb): its camera is read as the specification's */
    bool collada;     /* a COLLADA file (.dae, .zae): its camera's field of view is the whole angle */
    bool minus_z;     /* an ASE or LightWave scene (.ase, .ask, .lws): its camera looks down -Z */
    sl_missing_textures missing; /* a texture that names no file: refuse the model, or warn and drop it */
    /* Import from memory: the one file there is. */
    const char *mem_path;
    const unsigned char *mem;
    size_t mem_size;
    /* glTF: the triangles its triangle lists declare (gltf_check.c); -1 = not known. */
    long long triangles;
    /* The first file that could not be opened, and why. */
    char failed[SL_PATH_MAX];
    char failed_why[96];
} file_access;

typedef struct {
    unsigned char *bytes; /* owned unless `borrowed` */
    size_t size, pos;
    bool borrowed;
} open_file;

static size_t file_read(struct aiFile *f, char *buf, size_t size, size_t count)
{
    open_file *o = (open_file *)f->UserData;
    if (size == 0)
        return 0;
    size_t left = o->size - o->pos, n = count <= left / size ? count : left / size;
    memcpy(buf, o->bytes + o->pos, n * size);
    o->pos += n * size;
    return n;
}
static size_t file_write(struct aiFile *f, const char *buf, size_t size, size_t count)
{
    (void)f, (void)buf, (void)size, (void)count;
    return 0; /* import only */
}
static size_t file_tell(struct aiFile *f) { return ((open_file *)f->UserData)->pos; }
static size_t file_size(struct aiFile *f) { return ((open_file *)f->UserData)->size; }
static void file_flush(struct aiFile *f) { (void)f; }
static enum aiReturn file_seek(struct aiFile *f, size_t offset, enum aiOrigin origin)
{
    open_file *o = (open_file *)f->UserData;
    size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? o->pos : o->size;
    if (offset > o->size - base)
        return aiReturn_FAILURE;
    o->pos = base + offset;
    return aiReturn_SUCCESS;
}

static void note_failure(file_access *fa, const char *path, const char *why)
{
    if (!fa->failed[0]) {
        snprintf(fa->failed, sizeof fa->failed, "%s", path);
        snprintf(fa->failed_why, sizeof fa->failed_why, "%s", why);
    }
}

/* Reads a whole regular file of at most SL_MODEL_MAX_FILE_BYTES; NULL (with the reason noted)
 * otherwise. */
static unsigned char *read_regular(file_access *fa, const char *path, size_t *size)
{
    struct stat st;
    if (stat(path, &st) != 0) {
        note_failure(fa, path, errno == ENOENT ? "no such file" : strerror(errno));
        return NULL;
    }
    if (!S_ISREG(st.st_mode)) {
        note_failure(fa, path, "not a regular file");
        return NULL;
    }
    if ((unsigned long long)st.st_size > SL_MODEL_MAX_FILE_BYTES) {
        note_failure(fa, path, "larger than the 256 MiB a model file may have");
        return NULL;
    }
    FILE *f = fopen(path, "rb");
    unsigned char *bytes = malloc((size_t)st.st_size + 1);
    size_t n = f && bytes ? fread(bytes, 1, (size_t)st.st_size, f) : 0;
    if (f)
        fclose(f);
    if (!f || !bytes || n != (size_t)st.st_size) {
        free(bytes);
        note_failure(fa, path, !f ? "cannot open" : !bytes ? "out of memory" : "read error");
        return NULL;
    }
    *size = n;
    return bytes;
}

static struct aiFile *file_open(struct aiFileIO *io, const char *path, const char *mode)
{
    file_access *fa = (file_access *)io->UserData;
    if (!path || !mode || strchr(mode, 'w') || strchr(mode, 'a') || strchr(mode, '+'))
        return NULL;
    open_file *o = calloc(1, sizeof *o);
    struct aiFile *f = calloc(1, sizeof *f);
    if (!o || !f) {
        free(o);
        free(f);
        return NULL;
    }
    if (fa->mem) {
        if (strcmp(path, fa->mem_path) != 0) {
            note_failure(fa, path, "not reachable from a model in memory");
            free(o);
            free(f);
            return NULL;
        }
        o->bytes = (unsigned char *)fa->mem;
        o->size = fa->mem_size;
        o->borrowed = true;
    } else if (!(o->bytes = read_regular(fa, path, &o->size))) {
        free(o);
        free(f);
        return NULL;
    }
    *f = (struct aiFile){.ReadProc = file_read,
                         .WriteProc = file_write,
                         .TellProc = file_tell,
                         .FileSizeProc = file_size,
                         .SeekProc = file_seek,
                         .FlushProc = file_flush,
                         .UserData = (aiUserData)o};
    return f;
}

static void file_close(struct aiFileIO *io, struct aiFile *f)
{
    (void)io;
    if (!f)
        return;
    open_file *o = (open_file *)f->UserData;
    if (o && !o->borrowed)
        free(o->bytes);
    free(o);
    free(f);
}

/* ---- conversions ---- */

/* assimp's matrices are row-major (a1..a4 the first row); mat4 is column-major. */
static mat4 from_ai(const struct aiMatrix4x4 *m)
{
    return (mat4){{{m->a1, m->b1, m->c1, m->d1},
                   {m->a2, m->b2, m->c2, m->d2},
                   {m->a3, m->b3, m->c3, m->d3},
                   {m->a4, m->b4, m->c4, m->d4}}};
}

/* Y-up (assimp, glTF) to Z-up (softlight): +90 degrees about +X, (x, y, z) -> (x, -z, y). */
static mat4 y_up_to_z_up(void) { return (mat4){{{1, 0, 0, 0}, {0, 0, 1, 0}, {0, -1, 0, 0}, {0, 0, 0, 1}}}; }

static bool finite_mat4(mat4 m)
{
    for (int c = 0; c < 4; c++)
        if (!isfinite(m.c[c].x) || !isfinite(m.c[c].y) || !isfinite(m.c[c].z) || !isfinite(m.c[c].w))
            return false;
    return true;
}

static vec3 ai3(struct aiVector3D v) { return vec3(v.x, v.y, v.z); }
static bool finite3(vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

/* A direction perpendicular to unit n. */
static vec3 any_perpendicular(vec3 n)
{
    vec3 a = fabsf(n.x) < 0.9f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f);
    vec3 t;
    if (!sl_scene_safe_normalize(cross(n, a), &t))
        t = vec3(1.0f, 0.0f, 0.0f);
    return t;
}

/* ---- meshes ---- */

static bool convert_mesh(const char *name, unsigned index, const struct aiMesh *am, unsigned material_count,
                         sl_model_mesh *out, sl_error *err)
{
    char where[SL_PATH_MAX + 32];
    snprintf(where, sizeof where, "%s: mesh %u", name, index);
    if (!am->mVertices || am->mNumVertices == 0)
        return sl_fail(err, SL_ERR_FORMAT, "%s: has no vertex positions", where);
    if (am->mNumVertices > SCENE_MAX_VERTICES || am->mNumFaces > SCENE_MAX_TRIANGLES)
        return sl_fail(err, SL_ERR_RANGE, "%s: %u vertices / %u faces exceed the caps %d / %d", where,
                       am->mNumVertices, am->mNumFaces, SCENE_MAX_VERTICES, SCENE_MAX_TRIANGLES);
    if (am->mMaterialIndex >= material_count)
        return sl_fail(err, SL_ERR_FORMAT, "%s: material %u out of range (0..%u)", where, am->mMaterialIndex,
                       material_count ? material_count - 1 : 0);
    /* Triangles only (points and lines were removed); a face of another size is skipped. */
    int triangles = 0;
    for (unsigned f = 0; f < am->mNumFaces; f++)
        triangles += am->mFaces[f].mNumIndices == 3;
    bool uv = am->mTextureCoords[0] != NULL;
    sl_mesh *m = &out->mesh;
    if (!sl_scene_mesh_alloc(m, (int)am->mNumVertices, triangles, uv, where, err))
        return false;
    out->material = (int)am->mMaterialIndex;
    int t = 0;
    for (unsigned f = 0; f < am->mNumFaces; f++) {
        const struct aiFace *face = &am->mFaces[f];
        if (face->mNumIndices != 3)
            continue;
        for (int k = 0; k < 3; k++) {
            if (face->mIndices[k] >= am->mNumVertices)
                return sl_fail(err, SL_ERR_FORMAT, "%s: face %u: index %u out of range (0..%u)", where, f,
                               face->mIndices[k], am->mNumVertices - 1);
            m->indices[3 * (size_t)t + (size_t)k] = face->mIndices[k];
        }
        t++;
    }
    bool *keep = calloc(am->mNumVertices, sizeof *keep);
    if (!keep)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory", where);
    bool recompute = !am->mNormals;
    for (unsigned v = 0; v < am->mNumVertices; v++) {
        m->positions[v] = ai3(am->mVertices[v]);
        if (!isfinite(m->positions[v].x) || !isfinite(m->positions[v].y) || !isfinite(m->positions[v].z)) {
            free(keep);
            return sl_fail(err, SL_ERR_FORMAT, "%s: vertex %u: position is not finite", where, v);
        }
        /* A file's normal that cannot be normalised (zero, NaN) is regenerated from the faces. */
        keep[v] = am->mNormals && sl_scene_safe_normalize(ai3(am->mNormals[v]), &m->normals[v]);
        recompute = recompute || !keep[v];
        if (uv) {
            m->texcoords[v] = vec2(am->mTextureCoords[0][v].x, am->mTextureCoords[0][v].y);
            if (!isfinite(m->texcoords[v].x) || !isfinite(m->texcoords[v].y)) {
                free(keep);
                return sl_fail(err, SL_ERR_FORMAT, "%s: vertex %u: texture coordinate is not finite", where, v);
            }
        }
    }
    bool ok = !recompute || sl_scene_compute_normals(m, NULL, 0, keep);
    free(keep);
    if (!ok)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for normals", where);
    if (uv) {
        /* Gram-Schmidt against the final normal; w from the bitangent's side. A tangent the UVs
         * leave undefined (degenerate mapping) gets any perpendicular: it only matters under a
         * normal map, where such a mapping has no meaning anyway. */
        for (unsigned v = 0; v < am->mNumVertices; v++) {
            vec3 n = m->normals[v], t3;
            vec3 at = am->mTangents ? ai3(am->mTangents[v]) : vec3s(0.0f);
            if (!sl_scene_safe_normalize(sub3(at, scale3(n, dot3(n, at))), &t3))
                t3 = any_perpendicular(n);
            float w = 1.0f;
            if (am->mBitangents) {
                float s = dot3(cross(n, t3), ai3(am->mBitangents[v]));
                w = s < 0.0f ? -1.0f : 1.0f;
            }
            m->tangents[v] = vec4_from3(t3, w); /* allocated with the UVs */
        }
    }
    return sl_mesh_validate(m, where, err);
}

/* ---- node tree ---- */

typedef struct {
    const char *name;
    sl_model *model;
    unsigned mesh_count;
    int capacity;
    long flat; /* instances skipped: their node scales them to nothing */
    sl_error *err;
} walker;

/* The largest matrix element a node's transform may reach: past it, the positions of a model of
 * ordinary size leave the range where float depth and the rasterizer's fixed point hold. */
#define MODEL_TRANSFORM_MAX 1e15f

/* Depth-first over the node tree, composing transforms. A node tree from a file may be deep
 * or (if an importer let it) cyclic: depth is capped, and so is the number of instances. */
static bool walk(walker *w, const struct aiNode *node, mat4 parent, int depth)
{
    if (depth > SL_MODEL_MAX_NODE_DEPTH)
        return sl_fail(w->err, SL_ERR_FORMAT, "%s: nodes nested deeper than %d (recursive nodes?)", w->name,
                       SL_MODEL_MAX_NODE_DEPTH);
    mat4 world = mat4_mul(parent, from_ai(&node->mTransformation));
    if (!finite_mat4(world))
        return sl_fail(w->err, SL_ERR_FORMAT, "%s: node \"%.64s\": transform is not finite", w->name,
                       node->mName.data);
    float largest = 0.0f;
    for (int c = 0; c < 4; c++)
        largest = fmaxf(largest, fmaxf(fmaxf(fabsf(world.c[c].x), fabsf(world.c[c].y)),
                                       fmaxf(fabsf(world.c[c].z), fabsf(world.c[c].w))));
    if (largest > MODEL_TRANSFORM_MAX)
        return sl_fail(w->err, SL_ERR_RANGE, "%s: node \"%.64s\": transform out of range (an element of %g; at "
                       "most %g, where float coordinates still hold a model)", w->name, node->mName.data,
                       (double)largest, (double)MODEL_TRANSFORM_MAX);
    /* A node that scales its meshes to nothing (a zero matrix, a zero scale) places nothing. */
    vec3 x = xyz(world.c[0]), y = xyz(world.c[1]), z = xyz(world.c[2]);
    bool flat = dot3(cross(x, y), z) == 0.0f;
    for (unsigned i = 0; i < node->mNumMeshes; i++) {
        if (flat) {
            w->flat++;
            continue;
        }
        if (node->mMeshes[i] >= w->mesh_count)
            return sl_fail(w->err, SL_ERR_FORMAT, "%s: node \"%.64s\": mesh %u out of range", w->name,
                           node->mName.data, node->mMeshes[i]);
        if (w->model->instance_count == SL_MODEL_MAX_INSTANCES)
            return sl_fail(w->err, SL_ERR_RANGE, "%s: more than %d mesh instances", w->name,
                           SL_MODEL_MAX_INSTANCES);
        if (w->model->instance_count == w->capacity) {
            int cap = w->capacity ? 2 * w->capacity : 16;
            sl_model_instance *grown = realloc(w->model->instances, (size_t)cap * sizeof *grown);
            if (!grown)
                return sl_fail(w->err, SL_ERR_MEMORY, "%s: out of memory for instances", w->name);
            w->model->instances = grown;
            w->capacity = cap;
        }
        w->model->instances[w->model->instance_count++] = (sl_model_instance){(int)node->mMeshes[i], world};
    }
    for (unsigned c = 0; c < node->mNumChildren; c++)
        if (!walk(w, node->mChildren[c], world, depth + 1))
            return false;
    return true;
}

/* The world transform of the node called `name` (cameras are placed by name); identity when
 * no node has it. */
static bool find_node(const struct aiNode *node, const struct aiString *name, mat4 parent, int depth, mat4 *out)
{
    if (depth > SL_MODEL_MAX_NODE_DEPTH)
        return false;
    mat4 world = mat4_mul(parent, from_ai(&node->mTransformation));
    if (node->mName.length == name->length && memcmp(node->mName.data, name->data, name->length) == 0) {
        *out = world;
        return true;
    }
    for (unsigned c = 0; c < node->mNumChildren; c++)
        if (find_node(node->mChildren[c], name, world, depth + 1, out))
            return true;
    return false;
}

static void convert_camera(const struct aiScene *s, const file_access *fa, sl_model *model)
{
    bool gltf = fa->gltf, collada = fa->collada;
    const struct aiCamera *c = s->mCameras[0];
    mat4 node = mat4_identity();
    find_node(s->mRootNode, &c->mName, mat4_identity(), 0, &node);
    mat4 w = mat4_mul(y_up_to_z_up(), node);
    /* assimp documents the camera's position, look-at and up relative to its node, and
     * mHorizontalFOV as half the horizontal angle. Its glTF importer (5.2) copies the node's
     * translation into mPosition as well (placing the camera twice as far) and stores
     * yfov * aspectRatio: for glTF, the camera is the specification's (at the node's origin,
     * looking down -Z, +Y up) and yfov = mHorizontalFOV / aspect (measured, test_model). Its
     * COLLADA importer stores the file's whole xfov, not half of it (measured: xfov 37.85 arrives
     * as 0.6606 rad). Near and far are in the camera node's units: they scale with its world
     * transform as the eye does (a file in centimetres places the eye 100 times nearer and must
     * bring its clipping planes with it).
     * ASE and LightWave scenes: their importers (5.2) leave mLookAt at aiCamera's default,
     * +Z, for a camera that looks down its node's -Z: 3ds Max's cameras look down local -Z
     * (an ASE camera's target node lies on its -Z axis), and LightWave's look down +Z in its
     * left-handed space, which the LWS importer mirrors into right-handed nodes without
     * mirroring the camera. A look-at still at that default is read as -Z; one an importer set
     * otherwise is taken as it is. */
    float aspect = c->mAspect > 0.0f ? c->mAspect : 1.0f;
    float half_fovx = collada ? 0.5f * c->mHorizontalFOV : c->mHorizontalFOV;
    vec3 pos = gltf ? vec3s(0.0f) : ai3(c->mPosition);
    vec3 look = gltf ? vec3(0.0f, 0.0f, -1.0f) : ai3(c->mLookAt), up0 = gltf ? vec3(0.0f, 1.0f, 0.0f) : ai3(c->mUp);
    if (fa->minus_z && look.x == 0.0f && look.y == 0.0f && look.z == 1.0f)
        look.z = -1.0f;
    float fovy_rad = gltf ? c->mHorizontalFOV / aspect : 2.0f * atanf(tanf(half_fovx) / aspect);
    float fovy = fovy_rad * (180.0f / 3.14159265f);
    vec3 eye = xyz(mat4_mul_vec4(w, vec4_from3(pos, 1.0f)));
    vec3 dir = xyz(mat4_mul_vec4(w, vec4_from3(look, 0.0f)));
    vec3 up = xyz(mat4_mul_vec4(w, vec4_from3(up0, 0.0f)));
    float units = !gltf && length3(look) > 0.0f ? length3(dir) / length3(look) : 1.0f; /* glTF's are metres */
    vec3 f, u;
    if (!finite3(eye) || !(units > 0.0f) || !sl_scene_safe_normalize(dir, &f) || !sl_scene_safe_normalize(up, &u) ||
        length3(cross(f, u)) < 1e-3f || !(fovy > 0.1f && fovy < 179.0f) || !(c->mClipPlaneNear > 0.0f) ||
        !(c->mClipPlaneFar > c->mClipPlaneNear) || c->mOrthographicWidth > 0.0f)
        return; /* an orthographic or degenerate camera: the scene frames the bounds instead */
    model->camera = (sl_camera){.eye = eye,
                                .target = add3(eye, f),
                                .up = u,
                                .fovy_deg = fovy,
                                .znear = c->mClipPlaneNear * units,
                                .zfar = c->mClipPlaneFar * units};
    model->has_camera = true;
}

/* ---- materials and images ---- */

static void dir_of(const char *path, char out[SL_PATH_MAX])
{
    const char *slash = strrchr(path, '/');
    size_t n = slash ? (size_t)(slash - path) + 1 : 0;
    if (n >= SL_PATH_MAX)
        n = 0;
    memcpy(out, path, n);
    out[n] = '\0';
}

/* A missing texture skipped (SL_MISSING_TEXTURES_SKIP): its line in model->warnings, once
 * (a material naming one file in two slots, or two materials sharing a name, warn once). */
static void warn_missing(sl_model *model, const char *what)
{
    char line[720];
    int n = snprintf(line, sizeof line, "softlight: warning: %s; the material draws without it\n", what);
    if (n < 0 || (size_t)n >= sizeof line || strstr(model->warnings, line))
        return;
    size_t used = strlen(model->warnings);
    if (used + (size_t)n >= sizeof model->warnings) {
        model->warnings_left_out++;
        return;
    }
    memcpy(model->warnings + used, line, (size_t)n + 1);
}

/* The image `ref` (a material's texture path: "*N" for embedded texture N, a name an embedded
 * texture carries, or a file relative to the model) as an index into model->images, adding it
 * the first time. */
static bool find_image(const struct aiScene *s, sl_model *model, const char *dir, const char *ref,
                       const char *material, file_access *fa, int *index, sl_error *err)
{
    char shown[204];
    int embedded = -1;
    if (ref[0] == '*') {
        char *end;
        long n = strtol(ref + 1, &end, 10);
        if (*end || n < 0 || (unsigned long)n >= s->mNumTextures)
            return sl_fail(err, SL_ERR_FORMAT, "%s: embedded image \"%s\" out of range (%u images)", fa->name,
                           sl_error_excerpt(ref, 64, shown, sizeof shown), s->mNumTextures);
        embedded = (int)n;
    } else {
        for (unsigned i = 0; i < s->mNumTextures && embedded < 0; i++)
            if (s->mTextures[i]->mFilename.length && strcmp(s->mTextures[i]->mFilename.data, ref) == 0)
                embedded = (int)i;
    }
    char path[SL_PATH_MAX] = "";
    if (embedded < 0 && !sl_scene_texture_path_resolve(dir, ref, path)) {
        char mat[72], line[640];
        snprintf(line, sizeof line,
                 "%s: material \"%s\": texture \"%s\" not found in \"%s\" (also looked ignoring case, and for its "
                 "file name alone)",
                 fa->name, sl_error_excerpt(material, 64, mat, sizeof mat),
                 sl_error_excerpt(ref, 120, shown, sizeof shown), dir[0] ? dir : "./");
        if (fa->missing != SL_MISSING_TEXTURES_SKIP)
            return sl_fail(err, SL_ERR_IO, "%s", line);
        warn_missing(model, line);
        *index = -1;
        return true;
    }
    for (int i = 0; i < model->image_count; i++) {
        const sl_model_image *im = &model->images[i];
        if (embedded < 0 ? strcmp(im->path, path) == 0 : im->embedded == embedded) {
            *index = i;
            return true;
        }
    }
    if (model->image_count == SL_MODEL_MAX_IMAGES)
        return sl_fail(err, SL_ERR_RANGE, "%s: more than %d images", fa->name, SL_MODEL_MAX_IMAGES);
    sl_model_image *im = &model->images[model->image_count];
    memset(im, 0, sizeof *im);
    im->embedded = embedded;
    if (embedded < 0) {
        snprintf(im->path, sizeof im->path, "%s", path);
    } else {
        const struct aiTexture *tex = s->mTextures[embedded];
        size_t size = tex->mHeight ? (size_t)tex->mWidth * tex->mHeight * 4 : tex->mWidth;
        if (!tex->pcData || size == 0)
            return sl_fail(err, SL_ERR_FORMAT, "%s: embedded image %d is empty", fa->name, embedded);
        im->bytes = malloc(size);
        if (!im->bytes)
            return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for embedded image %d", fa->name, embedded);
        memcpy(im->bytes, tex->pcData, size);
        im->size = size;
        im->width = tex->mHeight ? (int)tex->mWidth : 0;
        im->height = (int)tex->mHeight;
        snprintf(im->format, sizeof im->format, "%.8s", tex->achFormatHint);
    }
    *index = model->image_count++;
    return true;
}

static bool texref(const struct aiScene *s, const struct aiMaterial *m, enum aiTextureType type, sl_model *model,
                   const char *dir, const char *material, file_access *fa, sl_model_texref *out, sl_error *err)
{
    *out = (sl_model_texref){.image = -1, .scale = 1.0f, .uv_scale = {1.0f, 1.0f}};
    struct aiString path;
    unsigned uv = 0;
    enum aiTextureMapMode mode[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
    if (aiGetMaterialTextureCount(m, type) == 0 ||
        aiGetMaterialTexture(m, type, 0, &path, NULL, &uv, NULL, NULL, mode, NULL) != aiReturn_SUCCESS)
        return true;
    if (path.length == 0)
        return true;
    out->uv_set = uv < 8 ? (int)uv : 0;
    int v = 0;
    static const int gl_wrap[4] = {10497, 33071, 33648, 33071}; /* wrap, clamp, mirror, decal */
    /* aiGetMaterialTexture reads one mode per axis when the material has both. */
    int ms = 0, mt = 0;
    if (aiGetMaterialIntegerArray(m, _AI_MATKEY_MAPPINGMODE_U_BASE, type, 0, &ms, NULL) == aiReturn_SUCCESS &&
        ms >= 0 && ms < 4)
        out->sampler.wrap_s = gl_wrap[ms];
    if (aiGetMaterialIntegerArray(m, _AI_MATKEY_MAPPINGMODE_V_BASE, type, 0, &mt, NULL) == aiReturn_SUCCESS &&
        mt >= 0 && mt < 4)
        out->sampler.wrap_t = gl_wrap[mt];
    if (aiGetMaterialIntegerArray(m, "$tex.mappingfiltermag", type, 0, &v, NULL) == aiReturn_SUCCESS)
        out->sampler.mag_filter = v;
    if (aiGetMaterialIntegerArray(m, "$tex.mappingfiltermin", type, 0, &v, NULL) == aiReturn_SUCCESS)
        out->sampler.min_filter = v;
    ai_real scale = 1.0f;
    if ((aiGetMaterialFloatArray(m, "$tex.scale", type, 0, &scale, NULL) == aiReturn_SUCCESS ||
         aiGetMaterialFloatArray(m, "$tex.strength", type, 0, &scale, NULL) == aiReturn_SUCCESS) &&
        isfinite(scale))
        out->scale = scale;
    /* A texture-coordinate transform (glTF's KHR_texture_transform, or a format's own): assimp
     * stores v' = v s + t for V-up coordinates, and FlipUVs, which gives softlight V-down ones
     * (v_down = 1 - v_up), negates t. In V-down coordinates that is v' = v s + (1 - s + t), and
     * glTF's offset comes back exactly (measured: offset 0.5, scale 3 arrive as t = 2.5). A
     * rotation has no place in a map's scale and offset: refused rather than drawn wrong. */
    struct aiUVTransform uvt;
    unsigned uvt_size = sizeof uvt / sizeof(ai_real);
    if (aiGetMaterialFloatArray(m, _AI_MATKEY_UVTRANSFORM_BASE, type, 0, (ai_real *)&uvt, &uvt_size) == aiReturn_SUCCESS &&
        uvt_size == sizeof uvt / sizeof(ai_real)) {
        if (!(isfinite(uvt.mScaling.x) && isfinite(uvt.mScaling.y) && isfinite(uvt.mTranslation.x) &&
              isfinite(uvt.mTranslation.y) && isfinite(uvt.mRotation)))
            return sl_fail(err, SL_ERR_FORMAT, "%s: material \"%.64s\": a texture transform that is not finite",
                           fa->name, material);
        if (fabsf(uvt.mRotation) > 1e-6f)
            return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: material \"%.64s\": a texture transform with a rotation "
                           "(%g rad), which softlight's maps (scale and offset) cannot express",
                           fa->name, material, (double)uvt.mRotation);
        out->uv_scale = vec2(uvt.mScaling.x, uvt.mScaling.y);
        out->uv_offset = vec2(uvt.mTranslation.x, 1.0f - uvt.mScaling.y + uvt.mTranslation.y);
    }
    return find_image(s, model, dir, path.data, material, fa, &out->image, err);
}

static float get_float(const struct aiMaterial *m, const char *key, unsigned type, unsigned index, float def,
                       bool *found)
{
    ai_real x = 0.0f;
    bool ok = aiGetMaterialFloatArray(m, key, type, index, &x, NULL) == aiReturn_SUCCESS && isfinite(x);
    if (found)
        *found = ok;
    return ok ? x : def;
}

static vec4 get_color(const struct aiMaterial *m, const char *key, unsigned type, unsigned index, vec4 def)
{
    struct aiColor4D c;
    if (aiGetMaterialColor(m, key, type, index, &c) != aiReturn_SUCCESS || !isfinite(c.r) || !isfinite(c.g) ||
        !isfinite(c.b) || !isfinite(c.a))
        return def;
    return vec4(c.r, c.g, c.b, c.a);
}

static float clamp01(float x) { return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x; }
static vec3 unit3(vec3 v) { return vec3(clamp01(v.x), clamp01(v.y), clamp01(v.z)); }

static bool convert_material(const struct aiScene *s, unsigned index, sl_model *model, const char *dir,
                             file_access *fa, sl_error *err)
{
    const struct aiMaterial *m = s->mMaterials[index];
    sl_model_material *out = &model->materials[index];
    struct aiString name;
    if (aiGetMaterialString(m, AI_MATKEY_NAME, &name) == aiReturn_SUCCESS && name.length)
        sl_error_excerpt(name.data, SL_NAME_MAX - 5, out->name, sizeof out->name);
    else
        snprintf(out->name, sizeof out->name, "material%u", index);
    bool metallic_found;
    float metallic = get_float(m, AI_MATKEY_METALLIC_FACTOR, 1.0f, &metallic_found);
    out->kind = metallic_found ? SL_MODEL_MAT_METALLIC_ROUGHNESS : SL_MODEL_MAT_PHONG;
    vec4 diffuse = get_color(m, AI_MATKEY_COLOR_DIFFUSE, vec4(1.0f, 1.0f, 1.0f, 1.0f));
    if (out->kind == SL_MODEL_MAT_METALLIC_ROUGHNESS) {
        vec4 b = get_color(m, AI_MATKEY_BASE_COLOR, diffuse);
        out->base_color = vec4(clamp01(b.x), clamp01(b.y), clamp01(b.z), clamp01(b.w));
        out->metallic = clamp01(metallic);
        out->roughness = clamp01(get_float(m, AI_MATKEY_ROUGHNESS_FACTOR, 1.0f, NULL));
    } else {
        out->kd = unit3(xyz(diffuse));
        out->ks = unit3(xyz(get_color(m, AI_MATKEY_COLOR_SPECULAR, vec4(0.0f, 0.0f, 0.0f, 1.0f))));
        /* MTL's Ns, the Phong exponent; assimp stores 0 when absent. */
        out->ns = get_float(m, AI_MATKEY_SHININESS, 0.0f, NULL);
        out->ns = out->ns < 0.0f ? 0.0f : out->ns > 1e6f ? 1e6f : out->ns;
        float opacity = clamp01(get_float(m, AI_MATKEY_OPACITY, 1.0f, NULL));
        out->base_color = vec4_from3(out->kd, opacity);
        out->roughness = 1.0f;
    }
    out->emissive = unit3(xyz(get_color(m, AI_MATKEY_COLOR_EMISSIVE, vec4(0.0f, 0.0f, 0.0f, 1.0f))));
    struct aiString mode;
    out->alpha_mode = SL_ALPHA_OPAQUE;
    if (aiGetMaterialString(m, AI_MATKEY_GLTF_ALPHAMODE, &mode) == aiReturn_SUCCESS) {
        if (strcmp(mode.data, "MASK") == 0)
            out->alpha_mode = SL_ALPHA_MASK;
        else if (strcmp(mode.data, "BLEND") == 0)
            out->alpha_mode = SL_ALPHA_BLEND;
    }
    out->alpha_cutoff = clamp01(get_float(m, AI_MATKEY_GLTF_ALPHACUTOFF, 0.5f, NULL));
    int two = 0;
    out->double_sided =
        aiGetMaterialIntegerArray(m, AI_MATKEY_TWOSIDED, &two, NULL) == aiReturn_SUCCESS && two != 0;

    bool mr = out->kind == SL_MODEL_MAT_METALLIC_ROUGHNESS;
    sl_model_texref none;
    bool ok = texref(s, m, mr ? aiTextureType_BASE_COLOR : aiTextureType_DIFFUSE, model, dir, out->name, fa,
                     &out->base_color_tex, err) &&
              texref(s, m, aiTextureType_EMISSIVE, model, dir, out->name, fa, &out->emissive_tex, err) &&
              texref(s, m, aiTextureType_NORMALS, model, dir, out->name, fa, &out->normal_tex, err);
    if (ok && mr) {
        /* Where assimp's glTF importer puts metallicRoughnessTexture and occlusionTexture. */
        ok = texref(s, m, aiTextureType_UNKNOWN, model, dir, out->name, fa, &out->metallic_roughness_tex, err) &&
             texref(s, m, aiTextureType_LIGHTMAP, model, dir, out->name, fa, &out->occlusion_tex, err);
        out->specular_tex = (sl_model_texref){.image = -1, .scale = 1.0f, .uv_scale = {1.0f, 1.0f}};
    } else if (ok) {
        /* MTL: map_Ns, map_Ks, and map_Bump (HEIGHT) where there is no norm (NORMALS). */
        ok = texref(s, m, aiTextureType_SHININESS, model, dir, out->name, fa, &out->metallic_roughness_tex, err) &&
             texref(s, m, aiTextureType_SPECULAR, model, dir, out->name, fa, &out->specular_tex, err) &&
             texref(s, m, aiTextureType_HEIGHT, model, dir, out->name, fa, &none, err);
        if (ok && out->normal_tex.image < 0)
            out->normal_tex = none;
        out->occlusion_tex = (sl_model_texref){.image = -1, .scale = 1.0f, .uv_scale = {1.0f, 1.0f}};
    }
    return ok;
}

/* ---- the import ---- */

void sl_model_free(sl_model *model)
{
    if (!model)
        return;
    for (int i = 0; model->meshes && i < model->mesh_count; i++) {
        sl_mesh_free(&model->meshes[i].mesh);
    }
    for (int i = 0; model->images && i < model->image_count; i++)
        free(model->images[i].bytes);
    free(model->meshes);
    free(model->instances);
    free(model->materials);
    free(model->images);
    memset(model, 0, sizeof *model);
}

/* The first line of assimp's last error, masked, for a message. */
static const char *assimp_reason(char out[204])
{
    const char *e = aiGetErrorString();
    char line[201];
    size_t n = 0;
    for (; e && e[n] && e[n] != '\n' && n < 200; n++)
        line[n] = e[n];
    line[n] = '\0';
    return sl_error_excerpt(n ? line : "unknown error", 200, out, 204);
}

/* Whether every mesh is the placeholder assimp builds for a file without meshes (its
 * SkeletonMeshBuilder: a pyramid per bone, made for a file of cameras, lights or bones, with a
 * material of that name). Drawn, it would pass for the file's content. */
static bool only_placeholder(const struct aiScene *s)
{
    for (unsigned i = 0; i < s->mNumMeshes; i++) {
        const struct aiMesh *m = s->mMeshes[i];
        struct aiString name;
        if (!m || m->mMaterialIndex >= s->mNumMaterials ||
            aiGetMaterialString(s->mMaterials[m->mMaterialIndex], AI_MATKEY_NAME, &name) != aiReturn_SUCCESS ||
            strcmp(name.data, "SkeletonMaterial") != 0)
            return false;
    }
    return true;
}

static bool convert_scene(const struct aiScene *s, file_access *fa, sl_model *model, sl_error *err)
{
    const char *name = fa->name;
    if (!s->mRootNode)
        return sl_fail(err, SL_ERR_FORMAT, "%s: no node tree", name);
    if (s->mNumMeshes == 0 || only_placeholder(s))
        return sl_fail(err, SL_ERR_FORMAT, "%s: no triangle meshes (softlight draws triangles; the file holds only "
                       "cameras, lights, points, lines or bones)", name);
    if (s->mNumMeshes > SL_MODEL_MAX_MESHES || s->mNumMaterials > SL_MODEL_MAX_MATERIALS)
        return sl_fail(err, SL_ERR_RANGE, "%s: %u meshes / %u materials exceed the caps %d / %d", name,
                       s->mNumMeshes, s->mNumMaterials, SL_MODEL_MAX_MESHES, SL_MODEL_MAX_MATERIALS);
    if (fa->triangles >= 0) {
        long long got = 0;
        for (unsigned i = 0; i < s->mNumMeshes; i++)
            got += s->mMeshes[i]->mPrimitiveTypes == aiPrimitiveType_TRIANGLE ? s->mMeshes[i]->mNumFaces : 0;
        if (got < fa->triangles)
            return sl_fail(err, SL_ERR_FORMAT, "%s: %lld of its %lld triangles have an index out of range of their "
                           "vertices", name, fa->triangles - got, fa->triangles);
    }
    unsigned materials = s->mNumMaterials ? s->mNumMaterials : 1;
    model->meshes = calloc(s->mNumMeshes, sizeof *model->meshes);
    model->materials = calloc(materials, sizeof *model->materials);
    /* Every material has at most six texture slots. */
    size_t images = (size_t)materials * 6 < SL_MODEL_MAX_IMAGES ? (size_t)materials * 6 : SL_MODEL_MAX_IMAGES;
    model->images = calloc(images, sizeof *model->images);
    if (!model->meshes || !model->materials || !model->images)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for %u meshes", name, s->mNumMeshes);
    model->material_count = (int)materials;
    char dir[SL_PATH_MAX];
    dir_of(model->path, dir);
    for (unsigned i = 0; i < s->mNumMaterials; i++)
        if (!convert_material(s, i, model, dir, fa, err))
            return false;
    if (s->mNumMaterials == 0) { /* assimp adds a default one; in case an importer did not */
        model->materials[0] = (sl_model_material){.name = "default", .kind = SL_MODEL_MAT_PHONG,
                                                  .base_color = vec4(0.5f, 0.5f, 0.5f, 1.0f), .kd = vec3s(0.5f),
                                                  .ks = vec3s(0.04f), .ns = 100.0f, .roughness = 1.0f};
        sl_model_texref none = {.image = -1, .scale = 1.0f, .uv_scale = {1.0f, 1.0f}};
        sl_model_material *d = &model->materials[0];
        d->base_color_tex = d->metallic_roughness_tex = d->normal_tex = d->occlusion_tex = d->emissive_tex =
            d->specular_tex = none;
    }
    /* Counted before it is filled, so that sl_model_free frees a mesh that failed half way. */
    for (unsigned i = 0; i < s->mNumMeshes; i++)
        if (model->mesh_count++, !convert_mesh(name, i, s->mMeshes[i], materials, &model->meshes[i], err))
            return false;
    walker w = {.name = name, .model = model, .mesh_count = s->mNumMeshes, .err = err};
    if (!walk(&w, s->mRootNode, y_up_to_z_up(), 0))
        return false;
    if (model->instance_count == 0)
        return sl_fail(err, SL_ERR_FORMAT, w.flat ? "%s: every node that places a mesh scales it to nothing (a zero "
                                                    "matrix or scale)"
                                                  : "%s: no node places a mesh",
                       name);
    if (s->mNumCameras > 0 && s->mCameras[0])
        convert_camera(s, fa, model);
    return true;
}

static bool is_gltf(const char *ext) { return strcasecmp(ext, "gltf") == 0 || strcasecmp(ext, "glb") == 0; }

static bool camera_minus_z(const char *ext)
{
    return !strcasecmp(ext, "ase") || !strcasecmp(ext, "ask") || !strcasecmp(ext, "lws");
}

static bool optional_companion(const char *path)
{
    static const char *const exts[] = {"md5anim", "md5camera", "skin", "shader"};
    const char *dot = strrchr(path, '.');
    for (size_t i = 0; dot && !strchr(dot, '/') && i < sizeof exts / sizeof exts[0]; i++)
        if (strcasecmp(dot + 1, exts[i]) == 0)
            return true;
    return false;
}

static bool import(const char *open_path, file_access *fa, sl_model *model, sl_error *err)
{
    struct aiFileIO io = {.OpenProc = file_open, .CloseProc = file_close, .UserData = (aiUserData)fa};
    struct aiPropertyStore *props = aiCreatePropertyStore();
    if (!props)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for the importer", fa->name);
    aiSetImportPropertyInteger(props, AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const struct aiScene *s = aiImportFileExWithProperties(open_path, IMPORT_FLAGS, &io, props);
    aiReleasePropertyStore(props);
    bool ok;
    char reason[204], shown[204];
    if (!s) {
        /* A file the import needed and could not open says more than assimp's message; one an
         * importer only looks for (an MD5 mesh's .md5anim and .md5camera, a Quake 3 model's
         * .skin and .shader) says nothing about why it failed. */
        bool needed = fa->failed[0] && !optional_companion(fa->failed);
        if (needed && strcmp(fa->failed, open_path) != 0)
            ok = sl_fail(err, SL_ERR_IO, "%s: names \"%s\", which cannot be read (%s)", fa->name,
                         sl_error_excerpt(fa->failed, 200, shown, sizeof shown), fa->failed_why);
        else if (needed)
            ok = sl_fail(err, SL_ERR_IO, "%s: %s", fa->name, fa->failed_why);
        else if (strstr(aiGetErrorString(), "No meshes remaining"))
            ok = sl_fail(err, SL_ERR_FORMAT, "%s: no triangle meshes (softlight draws triangles; the file holds only "
                         "points or lines)", fa->name);
        else if (strncmp(aiGetErrorString(), "No suitable reader", 18) == 0)
            ok = sl_fail(err, SL_ERR_FORMAT, "%s: no importer accepts its contents (truncated, or not the format its "
                         "extension says)", fa->name);
        else
            ok = sl_fail(err, SL_ERR_FORMAT, "%s: %s", fa->name, assimp_reason(reason));
    } else {
        ok = convert_scene(s, fa, model, err);
        aiReleaseImport(s);
    }
    if (!ok)
        sl_model_free(model);
    return ok;
}

/* One import, as sl_scene_import_isolated runs it in its child. */
typedef struct {
    const char *path;
    file_access *fa;
} import_job;

static bool import_job_run(void *ctx, sl_model *model, sl_error *err)
{
    import_job *job = ctx;
    memset(model, 0, sizeof *model);
    snprintf(model->path, sizeof model->path, "%s", job->path);
    return import(job->path, job->fa, model, err);
}

static const char *extension(const char *path)
{
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    return dot && (!slash || dot > slash) ? dot + 1 : "";
}

bool sl_path_is_scene(const char *path)
{
    const char *ext = extension(path);
    return strcasecmp(ext, "json") == 0;
}

bool sl_model_load(const char *path, sl_model *model, sl_error *err)
{
    return sl_model_load_with(path, SL_MISSING_TEXTURES_FAIL, model, err);
}

bool sl_model_load_with(const char *path, sl_missing_textures missing, sl_model *model, sl_error *err)
{
    memset(model, 0, sizeof *model);
    snprintf(model->path, sizeof model->path, "%s", path);
    char shown[80];
    const char *ext = extension(path);
    char dotted[40];
    snprintf(dotted, sizeof dotted, ".%.32s", ext);
    if (!ext[0])
        return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: no file extension (softlight tells a scene (.json) and the model "
                       "formats (.gltf, .glb, .obj, .fbx, ...) apart by it)", path);
    if (!aiIsExtensionSupported(dotted))
        return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: unknown model format \"%s\" (not a .json scene, nor a format assimp reads)",
                       path, sl_error_excerpt(dotted, 32, shown, sizeof shown));
    file_access fa = {.name = path, .gltf = is_gltf(ext), .collada = !strcasecmp(ext, "dae") || !strcasecmp(ext, "zae"),
                      .minus_z = camera_minus_z(ext), .missing = missing, .triangles = -1};
    struct stat st;
    if (stat(path, &st) != 0)
        return sl_fail(err, SL_ERR_IO, "%s: %s", path, errno == ENOENT ? "no such file" : strerror(errno));
    if (!S_ISREG(st.st_mode))
        return sl_fail(err, SL_ERR_IO, "%s: not a regular file", path);
    size_t input_bytes = (size_t)st.st_size;
    if (strcasecmp(ext, "obj") == 0 || strcasecmp(ext, "off") == 0) {
        size_t size;
        unsigned char *bytes = read_regular(&fa, path, &size);
        if (!bytes)
            return sl_fail(err, SL_ERR_IO, "%s: %s", path, fa.failed_why);
        char dir[SL_PATH_MAX];
        dir_of(path, dir);
        bool ok = strcasecmp(ext, "obj") == 0 ? sl_scene_obj_check((const char *)bytes, size, dir, path, err)
                                              : sl_scene_off_check((const char *)bytes, size, path, err);
        free(bytes);
        if (!ok)
            return false;
    }
    if (fa.gltf) {
        size_t size;
        scene_gltf_facts facts;
        unsigned char *bytes = read_regular(&fa, path, &size);
        if (!bytes)
            return sl_fail(err, SL_ERR_IO, "%s: %s", path, fa.failed_why);
        bool ok = sl_scene_gltf_check(bytes, size, strcasecmp(ext, "glb") == 0, path, &facts, err);
        free(bytes);
        if (!ok)
            return false;
        input_bytes += facts.buffer_bytes;
        fa.triangles = facts.triangles;
    }
    /* The import runs in a child bounded in memory and time, both from the input's size
     * (model_isolate.c says why). */
    if (input_bytes > SL_MODEL_MAX_FILE_BYTES)
        input_bytes = SL_MODEL_MAX_FILE_BYTES;
    size_t memory = SL_MODEL_IMPORT_MEMORY_BASE + SL_MODEL_IMPORT_MEMORY_PER_BYTE * input_bytes;
    int seconds = SL_MODEL_IMPORT_SECONDS_BASE + (int)(input_bytes >> 20) / SL_MODEL_IMPORT_MIB_PER_SECOND;
    import_job job = {.path = path, .fa = &fa};
    return sl_scene_import_isolated(import_job_run, &job, path, memory, seconds, model, err);
}

bool sl_model_load_memory(const void *data, size_t size, const char *hint, const char *name, sl_model *model,
                          sl_error *err)
{
    memset(model, 0, sizeof *model);
    snprintf(model->path, sizeof model->path, "%s", name);
    char path[64];
    snprintf(path, sizeof path, "memory.%.16s", hint);
    file_access fa = {.name = name, .gltf = is_gltf(hint),
                      .minus_z = camera_minus_z(hint), .mem_path = path, .mem = data, .mem_size = size, .triangles = -1};
    if (size > SL_MODEL_MAX_FILE_BYTES)
        return sl_fail(err, SL_ERR_RANGE, "%s: larger than the 256 MiB a model file may have", name);
    scene_gltf_facts facts;
    if (is_gltf(hint) && !sl_scene_gltf_check(data, size, strcasecmp(hint, "glb") == 0, name, &facts, err))
        return false;
    if (is_gltf(hint))
        fa.triangles = facts.triangles;
    if (strcasecmp(hint, "obj") == 0 && !sl_scene_obj_check(data, size, NULL, name, err))
        return false;
    if (strcasecmp(hint, "off") == 0 && !sl_scene_off_check(data, size, name, err))
        return false;
    return import(path, &fa, model, err);
}
