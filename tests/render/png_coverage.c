/* png_coverage FRAME.png BACKGROUND.png MIN MAX [warm|cool]: the share of pixels where FRAME
 * differs from BACKGROUND (by more than 24 of 255 in some channel) must lie in [MIN, MAX].
 * Prints it. warm / cool: only such pixels whose red exceeds blue by more than 40 (amber fluid),
 * or blue red (water). Used by the render smoke test: the fluid covers some of the frame, and
 * not all of it; a second material's colour shows where it is, and only there. */
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static unsigned char* load(const char* path, png_uint_32* w, png_uint_32* h) {
    png_image image;
    unsigned char* pixels;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path)) {
        fprintf(stderr, "png_coverage: %s: %s\n", path, image.message);
        return NULL;
    }
    image.format = PNG_FORMAT_RGB;
    pixels = (unsigned char*)malloc(PNG_IMAGE_SIZE(image));
    if (!pixels || !png_image_finish_read(&image, NULL, pixels, 0, NULL)) {
        fprintf(stderr, "png_coverage: %s: %s\n", path, image.message);
        free(pixels);
        return NULL;
    }
    *w = image.width;
    *h = image.height;
    return pixels;
}

int main(int argc, char** argv) {
    png_uint_32 w = 0, h = 0, bw = 0, bh = 0, i;
    unsigned char *frame, *background;
    unsigned long differ = 0;
    double share, lo, hi;
    int hue = 0; /* 1 warm, -1 cool, 0 any */
    if (argc != 5 && argc != 6) {
        fprintf(stderr, "usage: png_coverage FRAME.png BACKGROUND.png MIN MAX [warm|cool]\n");
        return 2;
    }
    if (argc == 6) hue = strcmp(argv[5], "warm") == 0 ? 1 : strcmp(argv[5], "cool") == 0 ? -1 : 2;
    if (hue == 2) {
        fprintf(stderr, "png_coverage: the fifth argument is warm or cool\n");
        return 2;
    }
    lo = atof(argv[3]);
    hi = atof(argv[4]);
    frame = load(argv[1], &w, &h);
    background = load(argv[2], &bw, &bh);
    if (!frame || !background) return 1;
    if (w != bw || h != bh) {
        fprintf(stderr, "png_coverage: sizes differ: %ux%u vs %ux%u\n", w, h, bw, bh);
        return 1;
    }
    for (i = 0; i < w * h; ++i) {
        int c, most = 0;
        for (c = 0; c < 3; ++c) {
            int d = abs((int)frame[3 * i + c] - (int)background[3 * i + c]);
            if (d > most) most = d;
        }
        if (most > 24 && (hue == 0 || hue * ((int)frame[3 * i] - (int)frame[3 * i + 2]) > 40)) ++differ;
    }
    share = (double)differ / ((double)w * (double)h);
    printf("png_coverage: %s differs from %s on %lu%s of %u pixels (%.1f %%; expected %.1f..%.1f %%)\n", argv[1],
           argv[2], differ,
           hue == 1    ? " warm"
           : hue == -1 ? " cool"
                       : "",
           w * h, 100.0 * share, 100.0 * lo, 100.0 * hi);
    free(frame);
    free(background);
    return share >= lo && share <= hi ? 0 : 1;
}
