/* png_check.c - for viewer_cli.sh: png_check FILE W H exits 0 when FILE is
 * a W x H PNG that is not blank (at least 1 % of its pixels differ from the
 * viewer's background), and says what is wrong otherwise. */
#include <stdio.h>
#include <stdlib.h>

#include "image.h"
#include "render.h"

int main(int argc, char **argv)
{
    if (argc != 4) return fprintf(stderr, "usage: png_check FILE W H\n"), 2;
    int w, h;
    unsigned char *rgb;
    pl_error err;
    if (vw_png_read(argv[1], &w, &h, &rgb, &err) != PL_OK)
        return fprintf(stderr, "png_check: %s: %s\n", argv[1], err.msg), 1;
    if (w != atoi(argv[2]) || h != atoi(argv[3]))
        return fprintf(stderr, "png_check: %s is %dx%d, expected %sx%s\n", argv[1], w, h, argv[2],
                       argv[3]), free(rgb), 1;
    long drawn = 0;
    for (long i = 0; i < (long)w * h; ++i) {
        int d = 0;
        for (int k = 0; k < 3; ++k) d += abs(rgb[3 * i + k] - (int)(VW_BACKGROUND[k] * 255 + 0.5f));
        drawn += d > 40;
    }
    free(rgb);
    if (drawn * 100 < (long)w * h)
        return fprintf(stderr, "png_check: %s is blank (%ld drawn pixels)\n", argv[1], drawn), 1;
    printf("%s: %dx%d, %ld drawn pixels\n", argv[1], w, h, drawn);
    return 0;
}
