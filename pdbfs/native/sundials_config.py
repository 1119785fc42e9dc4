"""The two headers SUNDIALS' CMake would generate, written by pdbfs for its
build of CVODE (double precision, 64-bit indices, no MPI, no logging, no
profiling) and valid for every compiler and target: nothing of SUNDIALS is
exported from a binary pdbfs builds."""

CONFIG_H = """\
/* sundials_config.h written by pdbfs (pdbfs/native/sundials_config.py) for
 * SUNDIALS 7.1.1 built without CMake: serial, double precision, 64-bit
 * indices, no MPI, no logging, no profiling, no third-party libraries. */
#ifndef _SUNDIALS_CONFIG_H
#define _SUNDIALS_CONFIG_H

#include "sundials/sundials_export.h"

#if defined(__cplusplus)
#define SUNDIALS_NOEXCEPT noexcept
#else
#define SUNDIALS_NOEXCEPT
#endif

#ifndef SUNDIALS_DEPRECATED_MSG
#  define SUNDIALS_DEPRECATED_MSG(msg)
#endif
#ifndef SUNDIALS_DEPRECATED_EXPORT_MSG
#  define SUNDIALS_DEPRECATED_EXPORT_MSG(msg) SUNDIALS_EXPORT
#endif
#ifndef SUNDIALS_DEPRECATED_NO_EXPORT_MSG
#  define SUNDIALS_DEPRECATED_NO_EXPORT_MSG(msg) SUNDIALS_NO_EXPORT
#endif

#define SUNDIALS_VERSION "7.1.1"
#define SUNDIALS_VERSION_MAJOR 7
#define SUNDIALS_VERSION_MINOR 1
#define SUNDIALS_VERSION_PATCH 1
#define SUNDIALS_VERSION_LABEL ""
#define SUNDIALS_GIT_VERSION ""

#if defined(__GNUC__) || defined(__clang__)
#define SUNDIALS_C_COMPILER_HAS_BUILTIN_EXPECT
#define SUNDIALS_C_COMPILER_HAS_ATTRIBUTE_UNUSED
#endif

#define SUNDIALS_DOUBLE_PRECISION 1
#define SUNDIALS_INT64_T 1
#define SUNDIALS_INDEX_TYPE int64_t

#define SUNDIALS_LOGGING_LEVEL 0
#define SUNDIALS_MPI_ENABLED 0

#define SUN_C_COMPILER "unknown"
#define SUN_C_COMPILER_VERSION ""
#define SUN_C_COMPILER_FLAGS ""
#define SUN_CXX_COMPILER ""
#define SUN_CXX_COMPILER_VERSION ""
#define SUN_CXX_COMPILER_FLAGS ""
#define SUN_FORTRAN_COMPILER ""
#define SUN_FORTRAN_COMPILER_VERSION ""
#define SUN_FORTRAN_COMPILER_FLAGS ""
#define SUN_BUILD_TYPE "Release"
#define SUN_JOB_ID ""
#define SUN_JOB_START_TIME ""
#define SUN_TPL_LIST ""
#define SUN_TPL_LIST_SIZE ""
#define SUNDIALS_SPACK_VERSION ""
#define SUN_MPI_C_COMPILER ""
#define SUN_MPI_C_VERSION ""
#define SUN_MPI_CXX_COMPILER ""
#define SUN_MPI_CXX_VERSION ""
#define SUN_MPI_FORTRAN_COMPILER ""
#define SUN_MPI_FORTRAN_VERSION ""

#define SUNDIALS_CVODES 1

#endif /* _SUNDIALS_CONFIG_H */
"""

EXPORT_H = """\
/* sundials_export.h written by pdbfs: SUNDIALS is compiled into each binary
 * and nothing of it is exported (hidden on ELF and Mach-O, no dllexport). */
#ifndef SUNDIALS_EXPORT_H
#define SUNDIALS_EXPORT_H
#if (defined(__GNUC__) || defined(__clang__)) && !defined(_WIN32) && !defined(__CYGWIN__)
#  define SUNDIALS_EXPORT __attribute__((visibility("hidden")))
#else
#  define SUNDIALS_EXPORT
#endif
#define SUNDIALS_NO_EXPORT SUNDIALS_EXPORT
#define SUNDIALS_DEPRECATED
#define SUNDIALS_DEPRECATED_EXPORT SUNDIALS_EXPORT
#define SUNDIALS_DEPRECATED_NO_EXPORT SUNDIALS_EXPORT
#endif
"""
