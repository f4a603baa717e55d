/* output.format (the VTU series, the Exodus II file or both) and the 3D view of output.picture
 * (docs/deck.md section 15, docs/output.md). */
#include <stdio.h>
#include <string.h>
#include "peri/error.h"
#include "peri/exodus_writer.h"
#include "setup_parts.h"

int peri_output_format_parse(peri_sim *s, const peri_node *output) {
  static const char *const formats[] = {"vtu", "exodus", "both", NULL};
  int which = 0;
  int rc = peri_deck_choice(output, "format", false, formats, &which);
  if (rc != PERI_OK) return rc;
  s->out.vtu = which != 1;
  s->out.exodus = which != 0;
  if (s->out.exodus && !peri_exodus_available())
    return peri_deck_error(peri_deck_get(output, "format"),
                           "key 'format': this peri was built without the Exodus II library; install "
                           "libexodusii-dev (scripts/install-deps) and rebuild, or write 'format: vtu'");
  return PERI_OK;
}

int peri_picture_view_parse(peri_sim *s, const peri_node *picture) {
  const bool given = peri_deck_get(picture, "view") || peri_deck_get(picture, "normal") || peri_deck_get(picture, "at");
  if (given && s->disc.geom.dim != 3) {
    const char *key = peri_deck_get(picture, "view") ? "view" : peri_deck_get(picture, "normal") ? "normal" : "at";
    return peri_deck_error(peri_deck_get(picture, key),
                           "key '%s': only 3D pictures have a view (a %dD picture shows the whole body)", key,
                           s->disc.geom.dim);
  }
  static const char *const views[] = {"slice", "projection", NULL};
  static const char *const axes[] = {"x", "y", "z", NULL};
  int view = 0, normal = s->out.picture_normal;
  int rc = peri_deck_choice(picture, "view", false, views, &view);
  if (rc == PERI_OK) rc = peri_deck_choice(picture, "normal", false, axes, &normal);
  if (rc == PERI_OK) rc = peri_deck_double(picture, "at", false, &s->out.picture_at);
  if (rc != PERI_OK) return rc;
  s->out.picture_projection = view == 1;
  s->out.picture_normal = normal;
  s->out.picture_at_given = peri_deck_get(picture, "at") != NULL;
  if (s->out.picture_at_given && s->out.picture_projection)
    return peri_deck_error(peri_deck_get(picture, "at"), "key 'at': a projection shows every node; 'at' places a "
                           "slice (view: slice)");
  return PERI_OK;
}
