// SPDX-License-Identifier: MIT
/*
 * One program reader (FUZZ_FORMAT: SH2000_PROG_GCODE, _CANON, _CSV or
 * _NURBS_JSON) on arbitrary text: no crash, no undefined behaviour, and
 * the promises of program.h (an error leaves the program empty and is in
 * the diagnostics; an accepted program has finite, connected geometry).
 */
#include <stdlib.h>

#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct sh2000_program p;
	struct sh2000_prog_diags d;
	int r;

	sh2000_program_init(&p);
	sh2000_prog_diags_init(&d);
	r = sh2000_program_read(&p, FUZZ_FORMAT, "fuzz", (const char *)data,
				size, NULL, &d);
	fz_check_program(r, &p, &d, (const char *)data, size);
	sh2000_program_free(&p);
	sh2000_prog_diags_free(&d);
	return 0;
}
