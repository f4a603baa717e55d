/* The series the peer comparisons read (bench/peers/README.md): runs an explicit deck
 * through the library, as `peri run` does but without output files, and prints every EVERY
 * steps (and at step 0) one line
 *   step  mean_damage  mean_broken_fraction  kinetic_energy  strain_energy
 * mean_damage: the mean of peri's damage index (beta-weighted, docs/models.md 5);
 * mean_broken_fraction: the mean over nodes of broken/all bonds of the family (LAMMPS
 * damage/atom with equal volumes). With NODES (not "-") the node set is first written
 * there, one node a line: x y z volume (17 digits), for the re-implementations to run on.
 *   peri_series DECK NODES EVERY [key.path=value ...] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/damage_index.h"
#include "peri/energies.h"
#include "peri/setup.h"
#include "peri/solver.h"

typedef struct series {
  long every;
  double *phi;
} series;

static void print_row(peri_sim *s, series *c) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  peri_damage_index(s, c->phi);
  double damage = 0.0, fraction = 0.0;
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const int64_t k0 = b->offset[i], k1 = b->offset[i + 1];
    long broken = 0;
    for (int64_t k = k0; k < k1; ++k) broken += b->broken[k];
    damage += c->phi[i];
    fraction += k1 > k0 ? (double)broken / (double)(k1 - k0) : 0.0;
  }
  const double n = p->n_owned > 0 ? (double)p->n_owned : 1.0;
  printf("%ld %.17g %.17g %.17g %.17g\n", s->state.step, damage / n, fraction / n, peri_kinetic_energy(s),
         peri_strain_energy(s));
  fflush(stdout);
}

static int hook(peri_sim *s, void *ctx) {
  series *c = ctx;
  if (s->state.step % c->every == 0) print_row(s, c);
  return 0;
}

int main(int argc, char **argv) {
  if (argc < 4) {
    fprintf(stderr, "usage: %s DECK NODES EVERY [key.path=value ...]\n", argv[0]);
    return 2;
  }
  peri_sim s;
  if (peri_sim_from_deck_with(&s, argv[1], argc - 4, (const char *const *)argv + 4) != 0) return 2;
  if (s.solver.kind != PERI_SOLVER_EXPLICIT) {
    fprintf(stderr, "%s: an explicit deck is needed\n", argv[1]);
    return 2;
  }
  const peri_particles *p = &s.disc.p;
  if (strcmp(argv[2], "-")) {
    FILE *f = fopen(argv[2], "w");
    if (!f) {
      perror(argv[2]);
      return 2;
    }
    for (int32_t i = 0; i < p->n_owned; ++i)
      fprintf(f, "%.17g %.17g %.17g %.17g\n", p->x[3 * i], p->x[3 * i + 1], p->x[3 * i + 2], p->volume[i]);
    fclose(f);
  }
  series c = {atol(argv[3]), malloc(sizeof(double) * (size_t)(p->n_owned > 0 ? p->n_owned : 1))};
  if (c.every < 1) c.every = 1;
  /* as peri_run: the initial conditions, the forces of the start, then the steps */
  peri_apply_initial_conditions(&s);
  peri_apply_loads(&s, s.state.time);
  s.mat.model->force(&s);
  s.state.forces_current = true;
  print_row(&s, &c);
  const int rc = peri_solve_explicit(&s, hook, &c);
  free(c.phi);
  peri_sim_free(&s);
  return rc == 0 ? 0 : 1;
}
