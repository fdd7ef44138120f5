/* xml_guard.h - private: parsing XML that nobody vouches for (scenes, VTU
 * meshes), shared by core/src/scene_xml.c and components/io/vtu.c. */
#ifndef PLIANT_XML_GUARD_H
#define PLIANT_XML_GUARD_H

#include <stddef.h>

#include <libxml/tree.h>

#include "pliant/error.h"

/* Parses len bytes of XML (any encoding libxml2 knows: UTF-8, UTF-16 LE or
 * BE with or without a byte order mark, ...) with network access off and
 * no entity substitution, then refuses any document type declaration: a
 * DTD is the only way to declare entities, neither scenes nor meshes need
 * one, and what is declared but not refused can expand (billion laughs) or
 * fetch (external entities).  The refusal is decided on what the parser
 * saw, never on the raw bytes, so no encoding slips past it; the parser is
 * stopped at "<!DOCTYPE" so that no entity declaration is even read.
 * `what` names the kind of document in messages ("scenes", "VTU files").
 * Returns the document (the caller frees it with xmlFreeDoc) or NULL with
 * err set: PL_EINPUT with `name` and the line, or PL_EINTERNAL. */
__attribute__((visibility("hidden"))) xmlDoc *pl_xml_read_untrusted(const char *buf, size_t len,
                                                                     const char *name,
                                                                     const char *what,
                                                                     int options, pl_error *err);

#endif
