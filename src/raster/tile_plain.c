/* tile_plain.c - the plain path (sl_raster_desc.plain) and programs that may discard and take
 * no derivative: pixel by pixel, one fragment shader call each (draw_tri, tile_internal.h)
 * (tile_internal.h maps the tile stage's files). */
#include "tile_internal.h"

void sl_rast_tri_plain_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri(c, full, x0, y0, x1, y1, true, false);
}

void sl_rast_tri_plain_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri(c, full, x0, y0, x1, y1, false, false);
}

/* A program that may discard and takes no derivative: pixel by pixel on both paths
 * (a span shader has no way to say which fragments it discarded). */
void sl_rast_tri_late_depth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri(c, full, x0, y0, x1, y1, true, true);
}

void sl_rast_tri_late_nodepth(tri_ctx *c, bool full, int x0, int y0, int x1, int y1)
{
    draw_tri(c, full, x0, y0, x1, y1, false, true);
}
