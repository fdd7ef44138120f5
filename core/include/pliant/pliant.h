/* pliant.h - the public SDK: include this one header. */
#ifndef PLIANT_H
#define PLIANT_H

#include "buffer.h"
#include "checked.h"
#include "component.h"
#include "draw.h"
#include "error.h"
#include "export.h"
#include "field.h"
#include "input.h"
#include "log.h"
#include "mesh.h"
#include "model.h"
#include "node.h"
#include "plugin.h"
#include "registry.h"
#include "roles.h"
#include "rows.h"
#include "sim.h"
#include "sofa.h"
#include "sparse.h"
#include "timer.h"
#include "work_limits.h"
#include "util.h"

#define PLIANT_VERSION_MAJOR 0
#define PLIANT_VERSION_MINOR 1

#endif
