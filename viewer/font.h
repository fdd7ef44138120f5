/* font.h - a 5 x 7 pixel bitmap font for ASCII 32..126, drawn for this
 * project (no font file, no third-party glyphs): the overlay's text. */
#ifndef PLIANT_VW_FONT_H
#define PLIANT_VW_FONT_H

enum { VW_FONT_W = 5, VW_FONT_H = 7, VW_FONT_CELL_W = 6, VW_FONT_CELL_H = 9,
       VW_FONT_FIRST = 32, VW_FONT_COUNT = 95 };

/* Whether pixel (x, y) of character ch is set (y = 0 is the top row);
 * characters outside 32..126 draw as '?'. */
int vw_font_pixel(int ch, int x, int y);
/* Fills an atlas of VW_FONT_COUNT cells side by side (width
 * VW_FONT_COUNT * VW_FONT_CELL_W, height VW_FONT_CELL_H), one byte per
 * pixel (255 = ink), glyphs at the top left of their cells. */
void vw_font_atlas(unsigned char *out);

#endif
