/* SPDX-License-Identifier: MIT */
/*
 * The library's own version, compiled in from the one project version in the
 * top-level CMakeLists.txt, so a tool reports the library it really loaded;
 * and the driver ABI it speaks, so a tool needs no driver header for it.
 */
#include "sh2000/sh2000.h"
#include "uapi/sh2000.h"

const char *sh2000_version(void)
{
	return SH2000_LIB_VERSION;
}

unsigned int sh2000_soversion(void)
{
	return SH2000_LIB_SOVERSION;
}

unsigned int sh2000_driver_abi(void)
{
	return SH2000_ABI_VERSION;
}
