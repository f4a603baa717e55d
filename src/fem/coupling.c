/* Row-wise PD-FEM coupling without overlap (002_b20c318388227af9.txt §2.1-2.1.1, MODELS.md
 * 14.1): "internal forces acting on a node are of the same nature as the node itself". The
 * row of an FEM node is the sum of the stiffness of the elements that contain it (its
 * columns include PD corners); the row of a PD node is its bonds to every neighbour, FEM or
 * PD: K_ij = lambda(|xi|) beta V_j xi (x) xi (2D, 3D) or lambda beta V_j (1D), K_ii = -sum_j K_ij.
 * Rows are in the force-density convention of the model tangents, so the implicit solver
 * assembles them as it assembles a model's tangent. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/coupling.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/fem.h"
#include "peri/fem_mesh.h"
#include "peri/sim.h"
#include "lattice_mesh.h"

double peri_coupling_micromodulus(int dim, peri_plane plane, double E, double alpha, double delta, double thickness,
                                  double cross_section) {
  if (dim == 1) return alpha < 3.0 ? (3.0 - alpha) * E / (cross_section * pow(delta, 3.0 - alpha)) : NAN;
  if (dim == 2) {
    const double K2D = plane == PERI_PLANE_STRAIN ? 0.8 * E : 0.75 * E; /* E/(2(1+nu)(1-2nu)), E/(2(1-nu)) */
    return alpha < 6.0 ? 4.0 * K2D * (6.0 - alpha) / (M_PI * thickness * pow(delta, 6.0 - alpha)) : NAN;
  }
  return alpha < 7.0 ? 3.0 * (7.0 - alpha) * E / (M_PI * pow(delta, 7.0 - alpha)) : NAN;
}

void peri_coupling_free(peri_coupling *c) {
  if (!c) return;
  free(c->node_type);
  free(c->c);
  free(c->element_offset);
  free(c->element_nodes);
  free(c->element_material);
  free(c->element_K);
  free(c->element_K_offset);
  free(c->fem_only);
  free(c->mesh_file);
  free(c->node_offset);
  free(c->node_element);
  if (c->lattice) peri_lattice_free(c->lattice);
  free(c->lattice);
  free(c->offset);
  free(c->offset_beta);
  free(c->switch_offset);
  free(c->balance_region);
  for (int k = 0; k < c->n_tractions; ++k) free(c->traction[k].name);
  free(c->traction);
  if (c->tangent_cols)
    for (int32_t i = 0; c->tangent_count && i < c->n_nodes; ++i) free(c->tangent_cols[i]), free(c->tangent_blocks[i]);
  free(c->tangent_count);
  free(c->tangent_cols);
  free(c->tangent_blocks);
  memset(c, 0, sizeof *c);
}

/* The stiffness of a lattice element of each material (all elements are the same cell). */
static int element_stiffness(const peri_sim *s, peri_coupling *c, char *why, size_t n) {
  const peri_geometry *g = &s->disc.geom;
  const int dim = g->dim, w = dim * c->corners;
  const double dx = g->spacing;
  c->element_K = peri_malloc(sizeof(double) * (size_t)s->mat.n_materials * (size_t)(w * w));
  for (int m = 0; m < s->mat.n_materials; ++m) {
    const peri_material *mat = &s->mat.materials[m];
    double *K = &c->element_K[(size_t)m * (size_t)(w * w)];
    int rc;
    if (dim == 1) {
      const double x[2] = {0.0, dx};
      rc = peri_fem_bar2_stiffness(x, mat->E, g->cross_section, K);
    } else if (dim == 2) {
      const double xy[8] = {0, 0, dx, 0, dx, dx, 0, dx};
      rc = peri_fem_quad4_stiffness(xy, mat->E, mat->nu, g->plane, g->thickness, K);
    } else {
      double xyz[24];
      static const int ca[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
      for (int a = 0; a < 8; ++a)
        for (int d = 0; d < 3; ++d) xyz[3 * a + d] = ca[a][d] * dx;
      rc = peri_fem_hex8_stiffness(xyz, mat->E, mat->nu, K);
    }
    if (rc != PERI_OK) {
      snprintf(why, n, "material %s: no element stiffness (spacing %g)", mat->name, dx);
      return rc;
    }
  }
  return PERI_OK;
}

/* The stiffness of each element of a mesh from its corners' positions: Q4 (with incompatible
 * modes where the mesh marks the element coarse) or triangle (2D), bar (1D), Hex8 (3D), of the
 * material of its first corner. */
static int mesh_stiffness(const peri_sim *s, const peri_fem_mesh *mesh, peri_coupling *c, char *why, size_t n) {
  const peri_geometry *g = &s->disc.geom;
  const peri_particles *p = &s->disc.p;
  const int dim = g->dim;
  c->element_K_offset = peri_malloc(sizeof(int64_t) * (size_t)(c->n_elements > 0 ? c->n_elements : 1));
  int64_t total = 0;
  for (int32_t e = 0; e < c->n_elements; ++e) {
    const int64_t w = dim * (c->element_offset[e + 1] - c->element_offset[e]);
    c->element_K_offset[e] = total;
    total += w * w;
  }
  c->element_K = peri_malloc(sizeof(double) * (size_t)(total > 0 ? total : 1));
  for (int32_t e = 0; e < c->n_elements; ++e) {
    const int32_t *en = &c->element_nodes[c->element_offset[e]];
    const int corners = (int)(c->element_offset[e + 1] - c->element_offset[e]);
    const peri_material *mat = &s->mat.materials[c->element_material[e]];
    double *K = &c->element_K[c->element_K_offset[e]], x[24];
    for (int a = 0; a < corners; ++a)
      for (int d = 0; d < dim; ++d) x[dim * a + d] = p->x[3 * (size_t)en[a] + d];
    int rc = PERI_ERR_INPUT;
    if (dim == 1 && corners == 2) rc = peri_fem_bar2_stiffness(x, mat->E, g->cross_section, K);
    else if (dim == 2 && corners == 3) rc = peri_fem_tri3_stiffness(x, mat->E, mat->nu, g->plane, g->thickness, K);
    else if (dim == 2 && corners == 4 && mesh->coarse[e])
      rc = peri_fem_quad4_incompatible_stiffness(x, mat->E, mat->nu, g->plane, g->thickness, K);
    else if (dim == 2 && corners == 4) rc = peri_fem_quad4_stiffness(x, mat->E, mat->nu, g->plane, g->thickness, K);
    else if (dim == 3 && corners == 8) rc = peri_fem_hex8_stiffness(x, mat->E, mat->nu, K);
    if (rc != PERI_OK && mesh->file) {
      snprintf(why, n, "%s: element %lld is inverted or degenerate", mesh->file, (long long)mesh->element_tag[e]);
      return PERI_ERR_INPUT;
    }
    if (rc != PERI_OK) {
      snprintf(why, n, "element %d (corners at nodes %d at (%g, %g, %g) ...) is inverted or degenerate", (int)e,
               (int)en[0], p->x[3 * (size_t)en[0]], p->x[3 * (size_t)en[0] + 1], p->x[3 * (size_t)en[0] + 2]);
      return PERI_ERR_INPUT;
    }
  }
  return PERI_OK;
}

/* The family offsets of the exact partial volumes: lattice offsets o != 0 whose cell (side dx,
 * centred at o dx) meets the horizon disk (1D: interval) of radius delta, with beta = the part
 * of the cell inside. */
static void exact_offsets(peri_coupling *c, int dim, double dx, double delta) {
  const int R = (int)ceil(delta / dx + 1.0);
  const int side = 2 * R + 1, total = dim == 1 ? side : side * side;
  c->offset = peri_malloc(sizeof(int32_t) * 3 * (size_t)total);
  c->offset_beta = peri_malloc(sizeof(double) * (size_t)total);
  c->n_offsets = 0;
  for (int b = dim == 1 ? 0 : -R; b <= (dim == 1 ? 0 : R); ++b)
    for (int a = -R; a <= R; ++a) {
      if (a == 0 && b == 0) continue;
      /* evaluated at (|a|, |b|): beta of o and -o are the same double, so the forces of a
       * pair of PD nodes cancel exactly */
      const int pa = abs(a), pb = abs(b);
      double beta;
      if (dim == 1) {
        const double lo = (pa - 0.5) * dx, hi = fmin((pa + 0.5) * dx, delta);
        beta = hi > lo ? (hi - lo) / dx : 0.0;
      } else {
        beta = peri_disk_rectangle_area((pa - 0.5) * dx, (pa + 0.5) * dx, (pb - 0.5) * dx, (pb + 0.5) * dx, delta) /
               (dx * dx);
      }
      if (!(beta > 1e-14)) continue; /* a cell that only touches the disk */
      int32_t *o = &c->offset[3 * (size_t)c->n_offsets];
      o[0] = a, o[1] = b, o[2] = 0;
      c->offset_beta[c->n_offsets++] = fmin(beta, 1.0);
    }
}

/* Keeps the tangent rows of PD nodes (the model calls it once per row in one process). */
static void keep_pd_row(void *ctx, int32_t i, int32_t count, const int32_t *cols, const double *blocks) {
  peri_coupling *c = ctx;
  if (!c->node_type[i] || count <= 0) return;
  c->tangent_count[i] = count;
  c->tangent_cols[i] = peri_malloc(sizeof(int32_t) * (size_t)count);
  c->tangent_blocks[i] = peri_malloc(sizeof(double) * 9 * (size_t)count);
  memcpy(c->tangent_cols[i], cols, sizeof(int32_t) * (size_t)count);
  memcpy(c->tangent_blocks[i], blocks, sizeof(double) * 9 * (size_t)count);
}

int peri_coupling_build(peri_sim *s, const int32_t *pd_nodes, int32_t n_pd_nodes, double alpha, double gamma,
                        bool exact_volumes, char *why, size_t n) {
  return peri_coupling_build_on_mesh(s, NULL, pd_nodes, n_pd_nodes, alpha, gamma, exact_volumes, why, n);
}

int peri_coupling_build_on_mesh(peri_sim *s, const peri_fem_mesh *mesh, const int32_t *pd_nodes, int32_t n_pd_nodes,
                                double alpha, double gamma, bool exact_volumes, char *why, size_t n) {
  const peri_geometry *g = &s->disc.geom;
  const peri_particles *p = &s->disc.p;
  peri_coupling *c = peri_calloc(1, sizeof *c);
  c->alpha = alpha, c->gamma = gamma;
  c->n_nodes = p->n_owned;
  c->node_type = peri_calloc((size_t)(p->n > 0 ? p->n : 1), sizeof(int32_t));
  for (int32_t k = 0; k < n_pd_nodes; ++k) c->node_type[pd_nodes[k]] = 1;
  c->n_pd = n_pd_nodes;
  c->c = peri_malloc(sizeof(double) * (size_t)s->mat.n_materials);
  for (int m = 0; m < s->mat.n_materials; ++m) {
    c->c[m] = gamma * peri_coupling_micromodulus(g->dim, g->plane, s->mat.materials[m].E, alpha, g->horizon,
                                                 g->thickness, g->cross_section);
    if (!isfinite(c->c[m])) {
      snprintf(why, n, "micromodulus_exponent %g: the family needs alpha < %d in %dD", alpha,
               g->dim == 1 ? 3 : g->dim == 2 ? 6 : 7, g->dim);
      peri_coupling_free(c), free(c);
      return PERI_ERR_INPUT;
    }
  }
  c->corners = 1 << g->dim;
  const bool from_file = mesh && mesh->file; /* its added nodes lie off the lattice */
  int rc = PERI_OK;
  if (!from_file) {
    c->lattice = peri_calloc(1, sizeof *c->lattice);
    rc = peri_lattice_build(p, g->dim, g->spacing, c->lattice, why, n);
  }
  if (rc == PERI_OK && mesh) { /* a graded mesh: its elements, each with its own stiffness */
    c->n_elements = mesh->n_elements;
    c->element_offset = peri_malloc(sizeof(int64_t) * ((size_t)mesh->n_elements + 1));
    memcpy(c->element_offset, mesh->offset, sizeof(int64_t) * ((size_t)mesh->n_elements + 1));
    const int64_t corners = mesh->offset[mesh->n_elements];
    c->element_nodes = peri_malloc(sizeof(int32_t) * (size_t)(corners > 0 ? corners : 1));
    memcpy(c->element_nodes, mesh->nodes, sizeof(int32_t) * (size_t)corners);
    c->fem_only = peri_malloc((size_t)(p->n > 0 ? p->n : 1));
    memcpy(c->fem_only, mesh->fem_only, (size_t)p->n_owned);
    c->coarse_nodes = mesh->coarse_nodes, c->removed_nodes = mesh->removed;
    if (from_file) c->mesh_file = peri_strdup(mesh->file);
    for (int32_t k = 0; k < n_pd_nodes && rc == PERI_OK; ++k)
      if (c->fem_only[pd_nodes[k]]) {
        const double *x = &p->x[3 * (size_t)pd_nodes[k]];
        const int64_t tag = from_file ? mesh->fem_only_tag[pd_nodes[k]] : 0;
        if (!from_file)
          snprintf(why, n, "PD node %d at (%g, %g, %g) lies within a horizon of the graded mesh's coarse part: "
                   "widen graded_mesh.fine around the PD zone", (int)pd_nodes[k], x[0], x[1], x[2]);
        else if (tag > 0)
          snprintf(why, n, "PD node %d at (%g, %g, %g): node %lld of %s lies within its horizon (plus dx) and off the "
                   "PD grid: the mesh's nodes must coincide with the PD grid of spacing %g near the PD zone",
                   (int)pd_nodes[k], x[0], x[1], x[2], (long long)tag, mesh->file, g->spacing);
        else if (tag < 0)
          snprintf(why, n, "PD node %d at (%g, %g, %g): element %lld of %s covers a point of the PD grid within its "
                   "horizon (plus dx) that is no node of the mesh: the mesh's nodes must coincide with the PD grid "
                   "of spacing %g near the PD zone", (int)pd_nodes[k], x[0], x[1], x[2], (long long)-tag, mesh->file,
                   g->spacing);
        else
          snprintf(why, n, "PD node %d at (%g, %g, %g) is node %lld of %s, which is not a node of the PD grid "
                   "(discretization.fill of spacing %g)", (int)pd_nodes[k], x[0], x[1], x[2],
                   (long long)mesh->node_tag[pd_nodes[k]], mesh->file, g->spacing);
        rc = PERI_ERR_INPUT;
      }
  } else if (rc == PERI_OK) { /* the lattice's own cells, all alike */
    int32_t *nodes = NULL;
    rc = peri_lattice_elements(c->lattice, p, c->node_type, &nodes, &c->n_elements, why, n);
    c->element_nodes = nodes;
    c->element_offset = peri_malloc(sizeof(int64_t) * ((size_t)c->n_elements + 1));
    for (int32_t e = 0; e <= c->n_elements; ++e) c->element_offset[e] = (int64_t)e * c->corners;
  }
  if (rc == PERI_OK && exact_volumes && g->dim == 3) {
    snprintf(why, n, "partial_volume exact: in 1D and 2D only (Ongaro 2022 gives no 3D rule)");
    rc = PERI_ERR_INPUT;
  }
  if (rc == PERI_OK && exact_volumes) exact_offsets(c, g->dim, g->spacing, g->horizon);
  c->exact_volumes = exact_volumes; /* else the bonds give the families */
  if (rc != PERI_OK) {
    peri_coupling_free(c), free(c);
    return rc;
  }
  /* an element's material is its first corner's; the elements of each node */
  c->element_material = peri_malloc(sizeof(int32_t) * (size_t)(c->n_elements > 0 ? c->n_elements : 1));
  c->node_offset = peri_calloc((size_t)p->n_owned + 1, sizeof(int64_t));
  for (int32_t e = 0; e < c->n_elements; ++e) {
    c->element_material[e] = p->material[c->element_nodes[c->element_offset[e]]];
    for (int64_t a = c->element_offset[e]; a < c->element_offset[e + 1]; ++a) c->node_offset[c->element_nodes[a] + 1]++;
  }
  for (int32_t i = 0; i < p->n_owned; ++i) c->node_offset[i + 1] += c->node_offset[i];
  c->node_element = peri_malloc(sizeof(int32_t) * (size_t)(c->node_offset[p->n_owned] + 1));
  int64_t *fill = peri_malloc(sizeof(int64_t) * ((size_t)p->n_owned + 1));
  memcpy(fill, c->node_offset, sizeof(int64_t) * ((size_t)p->n_owned + 1));
  for (int32_t e = 0; e < c->n_elements; ++e)
    for (int64_t a = c->element_offset[e]; a < c->element_offset[e + 1]; ++a) c->node_element[fill[c->element_nodes[a]]++] = e;
  free(fill);
  for (int32_t i = 0; mesh && i < p->n_owned && rc == PERI_OK; ++i)
    if (!c->node_type[i] && c->node_offset[i + 1] == c->node_offset[i] && mesh->file) {
      snprintf(why, n, "node %d at (%g, %g, %g) of the PD grid lies outside the mesh %s and is no PD node (an FEM "
               "node must be a node of the mesh; make it a PD node, or leave it out of discretization.fill)", (int)i,
               p->x[3 * (size_t)i], p->x[3 * (size_t)i + 1], p->x[3 * (size_t)i + 2], mesh->file);
      rc = PERI_ERR_INPUT;
    } else if (!c->node_type[i] && c->node_offset[i + 1] == c->node_offset[i]) {
      snprintf(why, n, "FEM node %d at (%g, %g, %g) belongs to no element of the graded mesh (make it a PD node, "
               "or fill the grid around it)", (int)i, p->x[3 * (size_t)i], p->x[3 * (size_t)i + 1],
               p->x[3 * (size_t)i + 2]);
      rc = PERI_ERR_INPUT;
    }
  if (rc == PERI_OK && mesh) {
    rc = mesh_stiffness(s, mesh, c, why, n);
  } else if (rc == PERI_OK) {
    rc = element_stiffness(s, c, why, n);
    const int64_t w = (int64_t)g->dim * c->corners;
    c->element_K_offset = peri_malloc(sizeof(int64_t) * (size_t)(c->n_elements > 0 ? c->n_elements : 1));
    for (int32_t e = 0; e < c->n_elements; ++e) c->element_K_offset[e] = c->element_material[e] * w * w;
  }
  if (rc != PERI_OK) {
    peri_coupling_free(c), free(c);
    return rc;
  }
  if (s->mat.model->tangent_reach == 2) { /* state-based: the linearised model's rows, kept */
    c->tangent_count = peri_calloc((size_t)(p->n > 0 ? p->n : 1), sizeof(int32_t));
    c->tangent_cols = peri_calloc((size_t)(p->n > 0 ? p->n : 1), sizeof(int32_t *));
    c->tangent_blocks = peri_calloc((size_t)(p->n > 0 ? p->n : 1), sizeof(double *));
    s->mat.model->tangent(s, keep_pd_row, c);
  }
  s->coupling = c;
  return PERI_OK;
}

/* The block a xi (x) xi of a bond (1D: a, since lambda multiplies u_j - u_i itself,
 * 002_b20c318388227af9.txt eq. 2.5), and its share of the diagonal. */
static inline void add_bond_block(int dim, double a, const double xi[3], double *diag, double *K) {
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q) {
      K[3 * r + q] = r < dim && q < dim ? (dim == 1 ? a : a * xi[r] * xi[q]) : 0.0;
      diag[3 * r + q] -= K[3 * r + q];
    }
}

/* Row of PD node i: its intact bonds, or with exact partial volumes the lattice nodes whose
 * cells meet its horizon. blocks[0] is the diagonal. Returns the column count. */
static int32_t pd_row(const peri_sim *s, int32_t i, int32_t *cols, double *blocks) {
  const peri_coupling *c = s->coupling;
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int dim = s->disc.geom.dim;
  double *diag = blocks;
  memset(diag, 0, 9 * sizeof(double));
  cols[0] = i;
  int32_t count = 1;
  const double ci = c->c[p->material[i]];
  if (c->tangent_count) { /* state-based: the kept row of the linearised model */
    memcpy(cols, c->tangent_cols[i], sizeof(int32_t) * (size_t)c->tangent_count[i]);
    memcpy(blocks, c->tangent_blocks[i], sizeof(double) * 9 * (size_t)c->tangent_count[i]);
    return c->tangent_count[i];
  }
  if (c->exact_volumes) { /* exact partial volumes: every lattice node whose cell meets the disk */
    for (int32_t q = 0; q < c->n_offsets; ++q) {
      int64_t k[3];
      for (int d = 0; d < 3; ++d) k[d] = c->lattice->cell[3 * (size_t)i + d] + c->offset[3 * (size_t)q + d];
      const int32_t j = peri_lattice_node(c->lattice, k);
      if (j < 0) continue;
      double xi[3];
      const double L = peri_bond_xi(p->x, i, j, xi);
      const double a = 0.5 * (ci + c->c[p->material[j]]) * pow(L, -c->alpha) * c->offset_beta[q] * p->volume[j];
      add_bond_block(dim, a, xi, diag, &blocks[9 * (size_t)count]);
      cols[count++] = j;
    }
    return count;
  }
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
    if (b->broken[k]) continue;
    const int32_t j = b->neighbor[k];
    double xi[3];
    const double L = peri_bond_xi(p->x, i, j, xi);
    const double lambda = 0.5 * (ci + c->c[p->material[j]]) * pow(L, -c->alpha);
    add_bond_block(dim, lambda * peri_bonds_beta(b, L) * p->volume[j], xi, diag, &blocks[9 * (size_t)count]);
    cols[count++] = j;
  }
  return count;
}

/* Row of FEM node i: -K^e / V_i of the elements that contain it, one block per distinct column. */
static int32_t fem_row(const peri_sim *s, int32_t i, int32_t *cols, double *blocks) {
  const peri_coupling *c = s->coupling;
  const int dim = s->disc.geom.dim;
  const double scale = -1.0 / s->disc.p.volume[i];
  int32_t count = 0;
  for (int64_t q = c->node_offset[i]; q < c->node_offset[i + 1]; ++q) {
    const int32_t e = c->node_element[q];
    const int32_t *en = &c->element_nodes[c->element_offset[e]];
    const int corners = (int)(c->element_offset[e + 1] - c->element_offset[e]), w = dim * corners;
    const double *K = &c->element_K[c->element_K_offset[e]];
    int a = 0;
    while (en[a] != i) ++a;
    for (int bn = 0; bn < corners; ++bn) {
      int32_t at = 0;
      while (at < count && cols[at] != en[bn]) ++at;
      if (at == count) {
        cols[count++] = en[bn];
        memset(&blocks[9 * (size_t)at], 0, 9 * sizeof(double));
      }
      for (int r = 0; r < dim; ++r)
        for (int t = 0; t < dim; ++t) blocks[9 * (size_t)at + 3 * r + t] += scale * K[(dim * a + r) * w + dim * bn + t];
    }
  }
  return count;
}

static int64_t longest_row(const peri_sim *s) {
  const peri_bonds *b = &s->disc.bonds;
  int64_t longest = 27 + 1; /* the corners of the elements of a node, at most 3^dim on the lattice */
  for (int32_t i = 0; s->coupling->fem_only && i < s->disc.p.n_owned; ++i) { /* a graded mesh: their sum */
    int64_t corners = 1;
    for (int64_t q = s->coupling->node_offset[i]; q < s->coupling->node_offset[i + 1]; ++q)
      corners += s->coupling->element_offset[s->coupling->node_element[q] + 1] -
                 s->coupling->element_offset[s->coupling->node_element[q]];
    if (corners > longest) longest = corners;
  }
  if (s->coupling->n_offsets + 1 > longest) longest = s->coupling->n_offsets + 1;
  for (int32_t i = 0; s->coupling->tangent_count && i < s->disc.p.n_owned; ++i)
    if (s->coupling->tangent_count[i] > longest) longest = s->coupling->tangent_count[i];
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i)
    if (b->offset[i + 1] - b->offset[i] + 1 > longest) longest = b->offset[i + 1] - b->offset[i] + 1;
  return longest;
}

void peri_coupling_rows(const peri_sim *s, peri_tangent_add_fn add, void *ctx) {
  const int64_t longest = longest_row(s);
  const int32_t *type = s->coupling->node_type;
#pragma omp parallel
  {
    int32_t *cols = peri_malloc(sizeof(int32_t) * (size_t)longest);
    double *blocks = peri_malloc(sizeof(double) * 9 * (size_t)longest);
#pragma omp for schedule(dynamic, 256)
    for (int32_t i = 0; i < s->disc.p.n_owned; ++i) {
      const int32_t count = type[i] ? pd_row(s, i, cols, blocks) : fem_row(s, i, cols, blocks);
#pragma omp critical(peri_coupling_rows_add)
      add(ctx, i, count, cols, blocks);
    }
    free(cols);
    free(blocks);
  }
}

void peri_coupling_switchable_rows(const peri_sim *s, peri_tangent_add_fn add, void *ctx) {
  const int64_t longest = longest_row(s);
  const peri_coupling *c = s->coupling;
#pragma omp parallel
  {
    int32_t *cols = peri_malloc(sizeof(int32_t) * (size_t)longest);
    double *blocks = peri_malloc(sizeof(double) * 9 * (size_t)longest);
#pragma omp for schedule(dynamic, 256)
    for (int32_t i = 0; i < s->disc.p.n_owned; ++i) {
      const bool fem = !c->node_type[i];
      int32_t count = fem ? fem_row(s, i, cols, blocks) : pd_row(s, i, cols, blocks);
#pragma omp critical(peri_coupling_rows_add)
      add(ctx, i, count, cols, blocks);
      if (fem && !(c->fem_only && c->fem_only[i])) { /* it may switch: its PD row too */
        count = pd_row(s, i, cols, blocks);
#pragma omp critical(peri_coupling_rows_add)
        add(ctx, i, count, cols, blocks);
      }
    }
    free(cols);
    free(blocks);
  }
}

void peri_coupling_force(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  const int64_t longest = longest_row(s);
  const int32_t *type = s->coupling->node_type;
#pragma omp parallel
  {
    int32_t *cols = peri_malloc(sizeof(int32_t) * (size_t)longest);
    double *blocks = peri_malloc(sizeof(double) * 9 * (size_t)longest);
#pragma omp for schedule(dynamic, 256)
    for (int32_t i = 0; i < p->n_owned; ++i) {
      const int32_t count = type[i] ? pd_row(s, i, cols, blocks) : fem_row(s, i, cols, blocks);
      double f[3] = {0, 0, 0};
      for (int32_t k = 0; k < count; ++k) {
        const double *K = &blocks[9 * (size_t)k], *u = &p->u[3 * (size_t)cols[k]];
        for (int r = 0; r < 3; ++r) f[r] += K[3 * r] * u[0] + K[3 * r + 1] * u[1] + K[3 * r + 2] * u[2];
      }
      for (int r = 0; r < 3; ++r) p->f[3 * (size_t)i + r] = f[r];
    }
    free(cols);
    free(blocks);
  }
}

void peri_coupling_nonlocal_traction(const peri_sim *s, const double x0[3], int axis, int sign, double out[3]) {
  const peri_particles *p = &s->disc.p;
  const peri_geometry *g = &s->disc.geom;
  const int dim = g->dim;
  const double dx = g->spacing, tol = 1e-6 * dx;
  const int64_t longest = longest_row(s);
  int32_t *cols = peri_malloc(sizeof(int32_t) * (size_t)longest);
  double *blocks = peri_malloc(sizeof(double) * 9 * (size_t)longest);
  /* each PD node's share, summed in the fixed blocks of peri_sum_owned: any thread and rank count */
  double *terms = peri_calloc(3 * (size_t)(p->n_owned > 0 ? p->n_owned : 1), sizeof(double));
  /* the cross-section of the line of PD nodes */
  const double section = dim == 1 ? g->cross_section : dim == 2 ? dx * g->thickness : dx * dx;
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!s->coupling->node_type[i]) continue;
    const double *xi = &p->x[3 * (size_t)i];
    bool on_line = true;
    for (int d = 0; d < dim; ++d)
      if (d != axis && fabs(xi[d] - x0[d]) > tol) on_line = false;
    const double depth = sign * (x0[axis] - xi[axis]); /* into the PD side */
    if (!on_line || !(depth > 0.0) || depth > g->horizon) continue;
    const int32_t count = pd_row(s, i, cols, blocks);
    double *t = &terms[3 * (size_t)i];
    for (int32_t k = 0; k < count; ++k) {
      const int32_t j = cols[k];
      if (j == i || s->coupling->node_type[j] || sign * (p->x[3 * (size_t)j + axis] - x0[axis]) <= 0.0) continue;
      const double *K = &blocks[9 * (size_t)k];
      for (int r = 0; r < 3; ++r)
        for (int q = 0; q < 3; ++q)
          t[r] += p->volume[i] / section * K[3 * r + q] * (p->u[3 * (size_t)j + q] - p->u[3 * (size_t)i + q]);
    }
  }
  peri_sum_owned(s, terms, 3, out);
  free(terms);
  free(cols);
  free(blocks);
}
