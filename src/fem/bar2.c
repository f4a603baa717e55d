/* The 2-node linear bar (002_b20c318388227af9.txt §2.1: k^e = (EA/dx)[[1,-1],[-1,1]]). */
#include "peri/error.h"
#include "peri/fem.h"

int peri_fem_bar2_stiffness(const double x[2], double E, double A, double K[4]) {
  const double L = x[1] - x[0];
  if (!(L > 0.0)) return PERI_ERR_INPUT;
  const double k = E * A / L;
  K[0] = k, K[1] = -k, K[2] = -k, K[3] = k;
  return PERI_OK;
}
