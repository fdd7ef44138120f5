/* xml_guard.c - XML parsing with document type declarations refused after
 * the parser has read the prologue (see xml_guard.h). */
#include "xml_guard.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

#include <libxml/parser.h>
#include <libxml/parserInternals.h>

/* Where the parser met a <!DOCTYPE>: 0 when it met none. */
typedef struct guard {
    int dtd_line;
} guard;

/* SAX2 calls this on "<!DOCTYPE name ..." before reading the internal
 * subset [...] or fetching an external one: stop right there. */
static void refuse_subset(void *ctx, const xmlChar *name, const xmlChar *external_id,
                          const xmlChar *system_id)
{
    xmlParserCtxtPtr c = ctx;
    guard *g = c->_private;
    if (!g->dtd_line) g->dtd_line = c->input ? c->input->line : 1;
    xmlStopParser(c);
}

static void malformed(xmlParserCtxtPtr ctxt, const char *name, pl_error *err)
{
    const xmlError *e = xmlCtxtGetLastError(ctxt);
    char msg[256];
    snprintf(msg, sizeof msg, "%s", e && e->message ? e->message : "unknown error");
    size_t n = strlen(msg);
    while (n && (msg[n - 1] == '\n' || msg[n - 1] == ' ')) msg[--n] = '\0';
    pl_error_set(err, PL_EINPUT, name, e && e->line > 0 ? e->line : 0, NULL, "malformed XML: %s",
                 msg);
}

xmlDoc *pl_xml_read_untrusted(const char *buf, size_t len, const char *name, const char *what,
                              int options, pl_error *err)
{
    if (len > INT_MAX) {
        pl_error_set(err, PL_EINPUT, name, 0, NULL, "the XML document is larger than 2 GiB");
        return NULL;
    }
    xmlParserCtxtPtr ctxt = xmlCreateMemoryParserCtxt(buf, (int)len);
    if (!ctxt) {
        pl_error_set(err, PL_EINTERNAL, name, 0, NULL, "out of memory");
        return NULL;
    }
    guard g = {0};
    ctxt->_private = &g;
    ctxt->sax->internalSubset = refuse_subset;
    ctxt->sax->externalSubset = refuse_subset;
    /* never substitute entities, load a DTD or touch the network */
    options &= ~(XML_PARSE_NOENT | XML_PARSE_DTDLOAD | XML_PARSE_DTDATTR | XML_PARSE_DTDVALID |
                 XML_PARSE_XINCLUDE | XML_PARSE_HUGE);
    options |= XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING;
    xmlCtxtUseOptions(ctxt, options);
    xmlParseDocument(ctxt);
    xmlDoc *doc = ctxt->myDoc;
    ctxt->myDoc = NULL;
    if (doc && !ctxt->wellFormed) {
        xmlFreeDoc(doc);
        doc = NULL;
    }
    /* the parsed document decides, whatever bytes spelled it */
    if (!g.dtd_line && doc && (doc->intSubset || doc->extSubset)) g.dtd_line = 1;
    if (g.dtd_line) {
        pl_error_set(err, PL_EINPUT, name, g.dtd_line, NULL,
                     "a document type declaration (a DTD: <!DOCTYPE>, <!ENTITY>) is refused in "
                     "%s: they never need one, and it can hide entity-expansion bombs and "
                     "external entities",
                     what);
        xmlFreeDoc(doc);
        doc = NULL;
    } else if (!doc) {
        malformed(ctxt, name, err);
    }
    xmlFreeParserCtxt(ctxt);
    return doc;
}
