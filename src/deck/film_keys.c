/* Films on substrates (docs/thin_films.md): the `imperfection` section, a small stress-free
 * transverse offset of a film's reference positions so that a compressed film does not stay
 * flat past its bifurcation, and the output keys interface_history, region_energy and
 * wrinkles. */
#include <math.h>
#include <stdint.h>
#include <string.h>
#include "peri/error.h"
#include "setup_parts.h"

#define TRY(x) do { int rc_ = (x); if (rc_ != PERI_OK) return rc_; } while (0)

/* A uniform number in [-1, 1) from the seed and a lattice column (splitmix64): the same on any
 * number of threads or ranks, since it depends on the column and not on the node order. */
static double column_random(uint64_t seed, int64_t a, int64_t b) {
  uint64_t z = seed * 0x9E3779B97F4A7C15ull + (uint64_t)a * 0xBF58476D1CE4E5B9ull + (uint64_t)b * 0x94D049BB133111EBull;
  for (int round = 0; round < 2; ++round) {
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
  }
  return (double)(z >> 11) * 0x1.0p-52 - 1.0;
}

/* Before the model's constants and the distribution over MPI ranks: every rank offsets the
 * whole problem's nodes the same way, and the weighted volumes see the offset geometry. */
int peri_setup_imperfection(peri_sim *s, const peri_node *root) {
  const peri_node *it = peri_deck_get(root, "imperfection");
  if (!it) return PERI_OK;
  static const char *const keys[] = {"region", "amplitude", "mode", "seed", "wavelength", NULL};
  static const char *const modes[] = {"random", "sine", NULL};
  TRY(peri_deck_allow(it, "imperfection", keys));
  const int dim = s->disc.geom.dim;
  if (dim < 2) return peri_deck_error(peri_deck_key_node(root, "imperfection"), "key 'imperfection': only in 2D and 3D");
  const char *name = NULL;
  double amplitude = 0.0, wavelength = 0.0;
  int mode = 0;
  long seed = 1;
  TRY(peri_deck_string(it, "region", true, &name));
  TRY(peri_deck_double(it, "amplitude", true, &amplitude));
  TRY(peri_deck_choice(it, "mode", false, modes, &mode));
  TRY(peri_deck_int(it, "seed", false, &seed));
  TRY(peri_deck_double(it, "wavelength", mode == 1, &wavelength));
  if (!(amplitude >= 0.0) || !isfinite(amplitude))
    return peri_deck_error(peri_deck_get(it, "amplitude"), "key 'amplitude': must be a length >= 0, got %g", amplitude);
  if (mode == 1 && !(wavelength > 0.0))
    return peri_deck_error(peri_deck_get(it, "wavelength"), "key 'wavelength': must be > 0, got %g", wavelength);
  if (mode == 0 && peri_deck_get(it, "wavelength"))
    return peri_deck_error(peri_deck_key_node(it, "wavelength"), "key 'wavelength': only with mode: sine");
  if (mode == 1 && peri_deck_get(it, "seed"))
    return peri_deck_error(peri_deck_key_node(it, "seed"), "key 'seed': only with mode: random");
  if (seed < 0) return peri_deck_error(peri_deck_get(it, "seed"), "key 'seed': must be >= 0, got %ld", seed);
  const int region = peri_setup_find_region(s, peri_deck_get(root, "regions"), peri_deck_get(it, "region"), name);
  if (region < 0) return -region;
  /* the transverse axis is y in 2D and z in 3D; each lattice column (x in 2D, x and y in 3D)
   * moves as one, so the film is offset, not roughened through its thickness */
  const int up = dim == 3 ? 2 : 1;
  const double dx = s->disc.family.spacing;
  peri_particles *p = &s->disc.p;
  const peri_region *r = &s->cond.regions[region];
  for (int32_t a = 0; a < r->count; ++a) {
    const int32_t i = r->nodes[a];
    const double *x = &p->x[3 * (size_t)i];
    const double offset = mode == 1 ? amplitude * sin(2.0 * M_PI * x[0] / wavelength)
                                    : amplitude * column_random((uint64_t)seed, llround(x[0] / dx),
                                                                dim == 3 ? llround(x[1] / dx) : 0);
    p->x[3 * (size_t)i + up] += offset;
  }
  return PERI_OK;
}

int peri_setup_film_output(peri_sim *s, const peri_node *root, const peri_node *output) {
  TRY(peri_deck_bool(output, "interface_history", false, &s->out.interface_history));
  TRY(peri_deck_bool(output, "region_energy", false, &s->out.region_energy));
  const char *name = NULL;
  TRY(peri_deck_string(output, "wrinkles", false, &name));
  if (!name) return PERI_OK;
  const peri_node *at = peri_deck_get(output, "wrinkles");
  if (s->disc.geom.dim != 2) return peri_deck_error(at, "key 'wrinkles': the deflection profile is of 2D runs");
  const int region = peri_setup_find_region(s, peri_deck_get(root, "regions"), at, name);
  if (region < 0) return -region;
  if (region == 0) return peri_deck_error(at, "key 'wrinkles': name the film's region, not 'all'");
  s->out.wrinkle_region = region;
  return PERI_OK;
}
