/* Runs a deck through an installed libperi (peri/api.h, built with pkg-config) and checks
 * the answer theory gives: the bar of bar.yaml ends at u = eps x at every node. */
#include <math.h>
#include <stdio.h>
#include <peri/api.h>

int main(int argc, char **argv) {
  const double eps = 1e-3; /* the strain bar.yaml imposes */
  peri_api *sim = NULL;
  if (argc != 3 || peri_api_open_deck(argv[1], 0, NULL, &sim) || peri_api_set_output(sim, argv[2]) ||
      peri_api_run(sim)) {
    fprintf(stderr, "bar: %s\n", argc != 3 ? "usage: bar DECK OUTPUT_DIR" : peri_api_last_error());
    return 1;
  }
  const double *x, *u;
  const int32_t *none;
  int ncomp;
  peri_api_field(sim, "reference_position", &x, &none, &ncomp);
  peri_api_field(sim, "displacement", &u, &none, &ncomp);
  const long n = peri_api_nodes(sim);
  double worst = 0.0; /* largest |u - eps x| / (eps L), L = 1 m */
  for (long i = 0; i < n; ++i) worst = fmax(worst, fabs(u[3 * i] - eps * x[3 * i]) / eps);
  printf("peri %s: %ld nodes, %ld load steps, largest |u - eps x| / (eps L) = %.3g\n", peri_api_version(), n,
         peri_api_step_index(sim), worst);
  peri_api_close(sim);
  return n == 100 && worst < 1e-6 ? 0 : 1;
}
