/* XML escaping shared by the VTU and PVD writers. */
#ifndef PERI_XML_ESCAPE_H
#define PERI_XML_ESCAPE_H
#include <stdio.h>

/* Writes text with the characters that cannot appear raw inside a double-quoted XML
 * attribute escaped. */
void peri_xml_attr_write(FILE *out, const char *text);

#endif
