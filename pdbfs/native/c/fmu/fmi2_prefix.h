/*
 * fmi2Functions.h with FMI2_FUNCTION_PREFIX honoured whichever copy of the
 * header the FMU was exported with: the standard one prefixes the FMI
 * functions when the build defines FMI2_FUNCTION_PREFIX, FMPy's copy (which
 * pdbfs takes the headers from) never does. The FMI 2.0 wrapper's files
 * include this instead of fmi2Functions.h.
 */
#ifndef PDBFS_FMI2_PREFIX_H
#define PDBFS_FMI2_PREFIX_H

#include "fmi2Functions.h"

#if defined(FMI2_FUNCTION_PREFIX)
#undef fmi2FullName
#define PDBFS_FMI2_PASTE(a, b) a##b
#define PDBFS_FMI2_PASTE_B(a, b) PDBFS_FMI2_PASTE(a, b)
#define fmi2FullName(name) PDBFS_FMI2_PASTE_B(FMI2_FUNCTION_PREFIX, name)
#endif

#endif
