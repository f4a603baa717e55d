/* Linear elastic finite elements (docs/coupling.md): element stiffness matrices of the
 * 2-node bar, the 4-node quadrilateral (2x2 Gauss points, plane stress or plane strain) and
 * the 8-node hexahedron (2x2x2 Gauss points). Degrees of freedom are node-major: node a,
 * component d is entry dim * a + d. Nodes of a quadrilateral go counter-clockwise; those of
 * a hexahedron go counter-clockwise around the face zeta = -1, then around zeta = +1. */
#ifndef PERI_FEM_H
#define PERI_FEM_H
#include "peri/material.h"

/* Bar between positions x[0] < x[1] of Young's modulus E and cross-section A:
 * K = (E A / L) [[1, -1], [-1, 1]] (2x2, row-major). Returns 0, or PERI_ERR_INPUT when the
 * length is not positive (coincident or reversed nodes). */
int peri_fem_bar2_stiffness(const double x[2], double E, double A, double K[4]);

/* Quadrilateral with corner coordinates xy[2a], xy[2a+1] (a = 0..3), thickness h, plane
 * stress or plane strain: K = sum over 2x2 Gauss points of B^T D B det(J) h (8x8). Returns 0,
 * or PERI_ERR_INPUT when det(J) <= 0 at a Gauss point (an inverted or degenerate element,
 * or corners in clockwise order). */
int peri_fem_quad4_stiffness(const double xy[8], double E, double nu, peri_plane plane, double h, double K[64]);

/* The same quadrilateral with the incompatible modes of QM6 (Taylor, Beresford & Wilson 1976):
 * exact in pure bending on a rectangle, and the patch test on any shape. Same returns. */
int peri_fem_quad4_incompatible_stiffness(const double xy[8], double E, double nu, peri_plane plane, double h,
                                          double K[64]);

/* Triangle with corner coordinates xy[2a], xy[2a+1] (a = 0..2, counter-clockwise), thickness
 * h: the constant-strain element, K = B^T D B A h (6x6). Returns 0, or PERI_ERR_INPUT when the
 * area is not positive (clockwise or collinear corners). */
int peri_fem_tri3_stiffness(const double xy[6], double E, double nu, peri_plane plane, double h, double K[36]);

/* The plane elasticity matrix D (Voigt, engineering shear strain) of plane stress or strain. */
void peri_fem_plane_elasticity(double E, double nu, peri_plane plane, double D[3][3]);

/* Hexahedron with corner coordinates xyz[3a + d] (a = 0..7): K = sum over 2x2x2 Gauss points
 * of B^T D B det(J) (24x24). Returns 0, or PERI_ERR_INPUT when det(J) <= 0 at a Gauss point. */
int peri_fem_hex8_stiffness(const double xyz[24], double E, double nu, double K[576]);

#endif
