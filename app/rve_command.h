/* peri rve: the nanocomposite RVE study from the command line (docs/microstructures.md section 7). */
#ifndef PERI_APP_RVE_COMMAND_H
#define PERI_APP_RVE_COMMAND_H
/* argv: the arguments after "rve"; returns the exit status (0, 1 failure, 2 bad input). */
int peri_rve_command(int argc, char **argv);
#endif
