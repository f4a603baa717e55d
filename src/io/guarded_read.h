/* Reading a file through a library that may crash, hang on memory or exit on a damaged file
 * (Gmsh, netCDF under Exodus II): the reading runs in a child process first (guarded_read.c). */
#ifndef PERI_IO_GUARDED_READ_H
#define PERI_IO_GUARDED_READ_H

/* Runs reader(context), the whole reading of PATH through LIBRARY (a name for messages), in a
 * child process with a bound on its memory (4 GiB more than the process has, plus 64 times the
 * file's size) and on its processor time (120 s plus 1 s a MB of the file), the child's
 * messages kept. When the child read the file, the reading runs again here and its result is
 * returned; otherwise the child's messages are reported here (a reader that refused the file),
 * or a message says the library crashed, ran out of time or ended the child, and PERI_ERR_INPUT
 * is returned. Where no child can be started the reading runs here unguarded. */
int peri_guarded_read(const char *path, const char *library, int (*reader)(void *context), void *context);
/* The same with the child's processor time bounded by `seconds`. */
int peri_guarded_read_within(const char *path, const char *library, int (*reader)(void *context), void *context,
                             unsigned seconds);
/* Runs job(context), a library's work on the file PATH that leaves its result in a file (Gmsh
 * meshing a geometry), in a child process only, without bounds on its time or memory (the work
 * may legitimately be long and large): PERI_OK when it succeeded there; a crash or a refusal
 * reported here as for a reading ("the Gmsh library crashed meshing it"), and PERI_ERR_INPUT.
 * Where no child can be started the job runs here. */
int peri_guarded_run(const char *path, const char *library, const char *doing, int (*job)(void *context),
                     void *context);

#endif
