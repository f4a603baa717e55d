/* PNG images into RGBA pixels with libpng's simplified API (include/peri/image_reader.h). */
#include <errno.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/image_reader.h"

int peri_image_read_rgba(const char *path, int *width, int *height, uint8_t **rgba) {
  *rgba = NULL;
  FILE *f = fopen(path, "rb");
  if (!f) {
    peri_error("image %s: cannot open: %s", path, strerror(errno));
    return PERI_ERR_INPUT;
  }
  png_image image;
  memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_stdio(&image, f)) {
    peri_error("image %s: not a readable PNG image (%s)", path, image.message);
    fclose(f);
    return PERI_ERR_INPUT;
  }
  /* sRGB 8-bit RGBA: libpng keeps 8-bit samples as they are in the file */
  image.format = PNG_FORMAT_RGBA;
  if (image.width == 0 || image.height == 0 || image.width > 100000 || image.height > 100000) {
    peri_error("image %s: %u x %u pixels is not a usable size (1 to 100000 per side)", path, image.width,
               image.height);
    png_image_free(&image);
    fclose(f);
    return PERI_ERR_INPUT;
  }
  uint8_t *buffer = peri_malloc(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, NULL, buffer, 0, NULL)) {
    peri_error("image %s: damaged PNG data (%s)", path, image.message);
    free(buffer);
    png_image_free(&image);
    fclose(f);
    return PERI_ERR_INPUT;
  }
  fclose(f);
  *width = (int)image.width;
  *height = (int)image.height;
  *rgba = buffer;
  return PERI_OK;
}
