/* Fragmenting cylinder (docs/verification.md case 10): with no external load the total linear
 * momentum stays zero while the tube stretches and bonds break. Pair forces are computed
 * identically from both ends, so each bond adds equal and opposite impulses and the
 * momentum changes only by round-off. */
#include <criterion/criterion.h>
#include <math.h>
#include "peri/damage.h"
#include "peri/energies.h"
#include "peri/setup.h"
#include "peri/solver.h"

Test(momentum, fragmenting_cylinder_conserves_momentum, .timeout = 300) {
  peri_sim s;
  cr_assert_eq(peri_sim_from_deck(&s, "examples/fragmenting_cylinder.yaml"), 0);
  s.solver.steps = 300; /* about 90 us: the tube is stretched well beyond the critical stretch */
  peri_apply_initial_conditions(&s);
  double scale = 0.0; /* sum of |m v|: the size of the momenta that cancel */
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) {
    double m = s.mat.materials[s.disc.p.material[i]].density * s.disc.p.volume[i];
    scale += m * sqrt(s.disc.p.v[3 * i] * s.disc.p.v[3 * i] + s.disc.p.v[3 * i + 1] * s.disc.p.v[3 * i + 1] +
                      s.disc.p.v[3 * i + 2] * s.disc.p.v[3 * i + 2]);
  }
  cr_assert_eq(peri_solve_explicit(&s, NULL, NULL), 0);
  double P[3];
  peri_linear_momentum(&s, P);
  double total = sqrt(P[0] * P[0] + P[1] * P[1] + P[2] * P[2]);
  long broken = peri_broken_count(&s.disc.bonds);
  cr_log_info("momentum %.3g of sum |m v| %.3g after %ld steps, %ld broken bonds", total, scale, s.state.step, broken);
  cr_expect(broken > 0, "the tube must start to fail");
  /* round-off: ~1e-16 per operation, accumulated over steps x bonds per node */
  cr_expect(total <= 1e-10 * scale, "linear momentum %g, scale %g", total, scale);
  peri_sim_free(&s);
}
