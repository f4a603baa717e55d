/* The interface-placement indicator D^2(u) of the PD-FEM coupling (002_b20c318388227af9.txt
 * eq. 2.115, MODELS.md 14.5; docs/coupling.md): the sum of the absolute second derivatives of
 * the displacement, fitted over each node's family. */
#ifndef PERI_INDICATOR_H
#define PERI_INDICATOR_H

typedef struct peri_sim peri_sim;

/* D2[i] = sum over components c and second derivatives of |d^2 u_c / dx_k dx_l| (k <= l) at each
 * owned node: in 2D |u1,xx| + |u1,yy| + |u1,xy| + |u2,xx| + |u2,yy| + |u2,xy|. The derivatives
 * are the weighted least-squares fit over the intact bonds of u_j - u_i = a . p(xi) with the
 * complete quadratic basis without constant (1D: xi, xi^2; 2D: 5 terms; 3D: 9 terms) and
 * weights omega beta V_j, exact for quadratic fields; 0 where the family cannot determine
 * them (too few bonds). */
void peri_second_derivative_indicator(const peri_sim *s, double *D2);

#endif
