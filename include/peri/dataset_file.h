/* The HDF5 file of a graph dataset (docs/datasets.md): groups, compressed arrays and
 * attributes, written so that the same contents give the same bytes (no modification
 * times, chunk shapes fixed by the array shapes, deflate with byte shuffling). It knows
 * nothing of simulations: src/post/dataset.c decides what goes in. */
#ifndef PERI_DATASET_FILE_H
#define PERI_DATASET_FILE_H
#include <stdbool.h>
#include <stdint.h>

typedef struct peri_dataset_file peri_dataset_file;

/* Whether this build writes dataset files (it was built with HDF5). */
bool peri_dataset_file_supported(void);
/* A new file at path (an existing one is replaced), or an existing one opened to add to
 * (append). NULL after a message naming the path. */
peri_dataset_file *peri_dataset_file_open(const char *path, bool append);
/* Closes the file: PERI_OK, or PERI_ERR_RUN after a message naming the path and the first
 * object that could not be written. */
int peri_dataset_file_close(peri_dataset_file *f);

/* Objects are named by their path from the root ("frames/000001/u"); a group must exist
 * before what it holds. A failed write is remembered and reported by close. */
void peri_dataset_file_group(peri_dataset_file *f, const char *path);
/* rows x cols arrays (cols 1: one dimension), little-endian in the file. */
void peri_dataset_file_doubles(peri_dataset_file *f, const char *path, int64_t rows, int cols, const double *data);
void peri_dataset_file_ints(peri_dataset_file *f, const char *path, int64_t rows, int cols, const int32_t *data);
void peri_dataset_file_bytes(peri_dataset_file *f, const char *path, int64_t rows, const uint8_t *data);
/* A fixed-length string dataset of `count` strings (names of materials, ...). */
void peri_dataset_file_strings(peri_dataset_file *f, const char *path, int count, const char *const *text);
/* Attributes of the object at `path` ("" or "/": the root). */
void peri_dataset_file_attr_double(peri_dataset_file *f, const char *path, const char *name, double value);
void peri_dataset_file_attr_long(peri_dataset_file *f, const char *path, const char *name, long value);
void peri_dataset_file_attr_string(peri_dataset_file *f, const char *path, const char *name, const char *value);

#endif
