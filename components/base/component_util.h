/* component_util.h - kept for older includes: the helpers are in the SDK. */
#include "pliant/util.h"
