/* XML attribute escaping. */
#include "xml_escape.h"

void peri_xml_attr_write(FILE *out, const char *text) {
  for (const char *c = text; *c; c++) {
    switch (*c) {
    case '&': fputs("&amp;", out); break;
    case '<': fputs("&lt;", out); break;
    case '>': fputs("&gt;", out); break;
    case '"': fputs("&quot;", out); break;
    default: fputc(*c, out);
    }
  }
}
