/* The parts of building a simulation from the deck that live in files of their own, called from setup.c:
 * heat conduction and thermomechanics (setup_thermal.c, docs/heat.md) and region lookup. */
#ifndef PERI_SETUP_PARTS_H
#define PERI_SETUP_PARTS_H
#include <stdbool.h>
#include "peri/deck.h"
#include "peri/discretize.h"
#include "peri/mesh.h"
#include "peri/sim.h"

/* Whether the deck asks for a conduction-only run (solver: {type: heat}). */
bool peri_setup_heat_only(const peri_node *root);
/* A material of a conduction-only run: density, conductivity, specific_heat. */
int peri_setup_heat_material(peri_sim *s, const peri_node *key, const peri_node *map, int index);
/* The optional thermal keys of a mechanical material (conductivity, specific_heat,
 * thermal_expansion). */
int peri_setup_material_thermal_keys(const peri_node *map, peri_material *mat);
/* Whether a boundary_conditions item has a thermal type (parsed by peri_setup_thermal). */
bool peri_setup_is_thermal_bc(const peri_node *item);
/* The thermal section, thermal conditions and the conduction operator; after the output
 * section is parsed and before the time step is set. */
int peri_setup_thermal(peri_sim *s, const peri_node *root);

/* Index of the region called `name`; on failure prints a message at `at` (with a
 * suggestion for a misspelling) and returns -PERI_ERR_INPUT (region_lookup.c). `regions`
 * is the deck's regions mapping (or NULL), whose keys are the regions after 'all'. */
int peri_setup_find_region(const peri_sim *s, const peri_node *regions, const peri_node *at,
                           const char *name);

/* output.format: vtu (default), exodus or both; exodus is an error at the key in a peri built
 * without the Exodus II library (output_keys.c). */
int peri_output_format_parse(peri_sim *s, const peri_node *output);
/* output.picture's view, normal and at (3D only; output_keys.c). */
int peri_picture_view_parse(peri_sim *s, const peri_node *picture);

/* Index of the material called `name`; on failure prints a message at `at` (with a
 * suggestion) and returns -PERI_ERR_INPUT (region_lookup.c). */
int peri_setup_find_material(const peri_sim *s, const peri_node *at, const char *name);

/* The discretization from discretization.mesh or node_file (mesh_keys.c, docs/deck.md
 * "Meshes"): the mesh's points become the particles, their blocks mapped to materials by
 * discretization.blocks. The mesh stays in *mesh for the regions (its sets and point ids). */
int peri_setup_mesh(peri_sim *s, const peri_node *d, peri_mesh *mesh);
/* A path of the deck (a node file, a mesh, an image): relative to the deck's directory, or
 * absolute (mesh_keys.c). */
void peri_setup_deck_path(const peri_sim *s, const char *path, char *full, size_t cap);

/* discretization.fictitious_layers (layer_keys.c): the layer nodes, after the regions and
 * before the bonds; and, once the conditions are parsed, the check that they prescribe them. */
int peri_setup_fictitious_layers(peri_sim *s, const peri_node *root);
int peri_setup_check_fictitious_layers(const peri_sim *s, const peri_node *root);

/* Whether a discretization.fill item is an image ({shape: image, ...}). */
bool peri_setup_is_image_fill(const peri_node *item);
/* An image fill item (image_keys.c, docs/microstructures.md): the PNG `file` read and its
 * pixels mapped to materials (or voids) by `colors`, at `pixel_size`, its lower-left corner
 * at `origin`. The fill's shape is the image's rectangle and out->phases its phase map
 * (allocated; free with peri_phase_map_free and free). `spacing` is the grid's, which must not
 * be finer than the pixels. */
int peri_setup_image_fill(const peri_sim *s, const peri_node *item, double spacing, peri_fill *out);
/* Whether a discretization.fill item is a detachment defect ({shape: detachment, ...}). */
bool peri_setup_is_detachment_fill(const peri_node *item);
/* A detachment fill item (detachment_keys.c, docs/microstructures.md section 3): out->detachment
 * (allocated; free it) and its `within` shape (the whole plane when absent). `spacing` is the
 * grid's: the thickness must reach the nodes next to the boundary. */
int peri_setup_detachment_fill(const peri_sim *s, const peri_node *item, double spacing, peri_fill *out);

/* The regions section (region_keys.c): shapes, mesh sets, node set files, blocks, materials
 * and their unions, intersections and differences. `mesh` is the discretization's mesh or
 * NULL (a grid); node_of_point[k] is the node of the mesh's point k. */
int peri_setup_regions(peri_sim *s, const peri_node *root, const peri_mesh *mesh, const int32_t *node_of_point);
/* Fictitious layer regions have every node's motion prescribed (after the boundary conditions). */
int peri_setup_check_layers(const peri_sim *s, const peri_node *root);

/* The j_integral section (j_integral_keys.c, docs/plasticity.md section 6): the crack tip,
 * its direction and the contours of the J-integral columns; after the model's init. */
int peri_setup_j_integral(peri_sim *s, const peri_node *root);

/* The coupling section (coupling_keys.c, docs/coupling.md): PD and FEM nodes, the structured
 * elements, the solver settings of the coupled stiffness; after the solver section. */
struct peri_fem_mesh;
int peri_setup_coupling(peri_sim *s, const peri_node *root, const struct peri_fem_mesh *mesh);
/* coupling.graded_mesh (coupling_keys.c, docs/coupling.md "Graded meshes"): on the grid of the
 * fill, before the nodes are ordered, leaves out the lattice nodes inside the coarse elements
 * and makes the mesh into m (left empty without the key). */
int peri_setup_graded_mesh(peri_sim *s, const peri_node *root, struct peri_fem_mesh *m);
/* discretization.horizon given as an expression of x, y, z (horizon_keys.c): whether it is
 * one (a plain number is not); the field at every node, after the nodes are ordered (an
 * error names the first node where it is not positive and finite); and, once the bonds
 * exist, the coupling region of discretization.partial_stress, the model's per-node form
 * and the combinations it rejects. s0_from_energy[m]: material m's critical stretch comes
 * from a fracture energy or toughness. */
bool peri_setup_horizon_is_field(const peri_node *discretization);
int peri_setup_horizon_field(peri_sim *s, const peri_node *discretization);
int peri_setup_horizon_coupling(peri_sim *s, const peri_node *root, const bool *s0_from_energy);
/* The solvers a horizon that varies rejects (after the solver section): implicit (no tangent),
 * and nlcg with a coupling region (the partial stress is not an energy's gradient). */
int peri_setup_horizon_solver(const peri_sim *s, const peri_node *root);
/* Precracks that cut a bond of the local nodes' coupling region (after they are applied): an
 * error naming the node, since cracks may only run in the full peridynamic region. */
int peri_setup_horizon_precracks(const peri_sim *s, const peri_node *root);
/* The contact section (contact_keys.c, docs/contact.md): short-range forces; after the
 * model's constants and the solver section. */
int peri_setup_contact(peri_sim *s, const peri_node *root);
/* The materials' plasticity keys (plasticity_keys.c, docs/plasticity.md): the sublayers of
 * every plastic material, after the elastic constants are resolved; then, once the solver is
 * parsed, whether the solver can carry a plastic state. */
int peri_setup_plasticity(peri_sim *s, const peri_node *root);
int peri_setup_plasticity_solver(peri_sim *s, const peri_node *root);

/* The bodies key (body_keys.c, docs/contact.md "Bodies"): regions that are separate bodies,
 * each node in at most one; the bonds between two bodies are removed. After the regions and
 * the bonds, before pre-cracks and the model's constants. */
int peri_setup_bodies(peri_sim *s, const peri_node *root);
/* output.penetration (body_keys.c): a mapping of body names to directions of travel; the face
 * of each from the reference positions (docs/contact.md "Bodies"). */
int peri_setup_penetration(peri_sim *s, const peri_node *root);
/* The tools key (tool_keys.c, docs/contact.md "Rigid tools"): rigid tools, after the solver
 * section (load control needs the explicit solver) and the initial displacements. */
int peri_setup_tools(peri_sim *s, const peri_node *root);

/* Films on substrates (film_keys.c, docs/thin_films.md): the imperfection section, a
 * transverse offset of a region's reference positions (after the regions and the bonds, before
 * the model's constants); and the output keys interface_history, region_energy and wrinkles
 * (in the output section). */
int peri_setup_imperfection(peri_sim *s, const peri_node *root);
int peri_setup_film_output(peri_sim *s, const peri_node *root, const peri_node *output);

#endif
