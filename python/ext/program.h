/* SPDX-License-Identifier: MIT */
/* sh2000._sh2000.Program (program.c, program_run.c). */
#ifndef SH2000_PY_PROGRAM_H
#define SH2000_PY_PROGRAM_H

#include "binding.h"

typedef struct {
	PyObject_HEAD
	PyCard *card;			/* holds the card open */
	char *path;			/* as given, for messages */
	struct sh2000_prog_reader *reader;
	struct sh2000_prog_diags diags;
	struct sh2000_path_config pc;	/* the card's, at open */
	double margin;			/* pc's at open: check() may plan
					 * with less, each from this one */
	struct sh2000_program_plan plan;
	int read;			/* a check() has read the reader */
	int checked;			/* plan is the last check()'s */
	int running;
} PyProgram;

/* The program is open, not running, its card open; else a Python error
 * and 0. */
int sh2k_program_ok(PyProgram *p);
/* sh2000.Error for e: msg and where, or (msg NULL) the first error in the
 * diagnostics; .diagnostics lists them all. Returns NULL. */
PyObject *sh2k_program_raise(PyProgram *p, int e, const char *msg,
			     const char *where);
PyObject *sh2k_program_run(PyProgram *p, PyObject *args);

#endif /* SH2000_PY_PROGRAM_H */
