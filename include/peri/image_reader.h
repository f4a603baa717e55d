/* Reading a raster image (PNG, through libpng) into 8-bit RGBA pixels (src/io/image_reader.c). */
#ifndef PERI_IMAGE_READER_H
#define PERI_IMAGE_READER_H
#include <stdint.h>

/* Reads `path` into *rgba (width * height * 4 bytes, row 0 the top row; free it). Any PNG
 * libpng reads (grey, palette, 16-bit, interlaced, with or without alpha) is converted to
 * 8-bit RGBA without gamma correction, so the colours are the file's own values. Returns
 * PERI_OK, or PERI_ERR_INPUT with a message naming the file. */
int peri_image_read_rgba(const char *path, int *width, int *height, uint8_t **rgba);

#endif
