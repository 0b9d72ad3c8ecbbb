/* coverage.c - a masked material's coverage lookup (coverage.h). */
#include "coverage.h"

#include "core/hash.h"

bool sl_coverage_of(const sl_material *m, const sl_scene_textures *tex, sl_coverage *c)
{
    if (!m->masked || !tex)
        return false;
    const bool mask = m->maps[SL_MAP_MASK].set;
    const sl_material_map *map = &m->maps[mask ? SL_MAP_MASK : SL_MAP_KD];
    if (!map->set || map->image < 0 || map->image >= tex->count || !tex->textures[map->image])
        return false; /* the program reads (1, 1, 1, 1) there: it keeps every fragment */
    c->map.texture = tex->textures[map->image];
    c->image = map->image;
    c->map.state = sl_gbuffer_map_sampler(map);
    c->st = vec4(map->uv_scale.x, map->uv_scale.y, map->uv_offset.x, map->uv_offset.y);
    c->channel = mask ? 0 : 3;
    c->cutoff = m->alpha_cutoff;
    return true;
}

uint64_t sl_coverage_hash(uint64_t h, const sl_coverage *c)
{
    const float numbers[5] = {c->cutoff, c->st.x, c->st.y, c->st.z, c->st.w};
    h = sl_fnv1a(h, numbers, sizeof numbers);
    h = sl_fnv1a(h, &c->channel, sizeof c->channel);
    const int state[4] = {(int)c->map.state.wrap_s, (int)c->map.state.wrap_t, (int)c->map.state.min_filter,
                          (int)c->map.state.mag_filter};
    h = sl_fnv1a(h, state, sizeof state);
    int w = 0, hgt = 0;
    const void *texels = sl_texture_level_texels(c->map.texture, 0, &w, &hgt);
    const sl_texture_format fmt = sl_texture_get_format(c->map.texture);
    h = sl_fnv1a(h, &fmt, sizeof fmt);
    h = sl_fnv1a(h, &w, sizeof w);
    h = sl_fnv1a(h, &hgt, sizeof hgt);
    if (texels)
        h = sl_fnv1a(h, texels, (size_t)w * (size_t)hgt * (size_t)sl_texture_format_bytes(fmt));
    return h;
}
