/* SPDX-License-Identifier: MIT */
/*
 * The built-in G-code reader's two halves, as LinuxCNC splits its
 * interpreter (interp_read and interp_convert): gcode_read.c turns a line
 * into words (struct gline: the G and M codes by modal group, the other
 * words with their values and columns), checking only what a word alone
 * can be wrong in; gcode.c interprets the words against the modal state.
 */
#ifndef SH2000_GCODE_READ_H
#define SH2000_GCODE_READ_H

#include <stdbool.h>
#include <stddef.h>

#include "prog_internal.h"

enum motion { MOT_NONE = -1, MOT_G0 = 0, MOT_G1 = 10, MOT_G2 = 20,
	      MOT_G3 = 30, MOT_G52 = 52, MOT_G53 = 53, MOT_G80 = 800 };

/* modal groups as LinuxCNC numbers them */
enum { GRP_NONMODAL = 0, GRP_MOTION = 1, GRP_PLANE = 2, GRP_DIST = 3,
       GRP_ARCDIST = 4, GRP_FEEDMODE = 5, GRP_UNITS = 6, GRP_CUTTER = 7,
       GRP_TOOLLEN = 8, GRP_COORD = 12, GRP_PATH = 13, GRP_COUNT = 16 };
enum { MGRP_STOP = 0, MGRP_TOOL = 1, MGRP_SPINDLE = 2, MGRP_COOLANT = 3,
       MGRP_COUNT = 4 };

#define G_UNKNOWN (-2)
#define G_UNSUPPORTED (-1)

struct gline {
	unsigned int line;
	unsigned int first_col;		/* first word other than N */
	int g[GRP_COUNT];		/* code * 10 per group, -1 none */
	unsigned int gcol[GRP_COUNT];
	int m[MGRP_COUNT];
	unsigned int mcol[MGRP_COUNT];
	bool has[26];
	double val[26];
	unsigned int col[26];
	bool any_word;
};

#define HAS(l, c) ((l)->has[(c) - 'A'])
#define VAL(l, c) ((l)->val[(c) - 'A'])
#define COL(l, c) ((l)->col[(c) - 'A'])

/* Split a line into words; 0, or an error already reported (the line is
 * then dropped). */
int gcode_lex_line(struct prog_ctx *c, const char *s, size_t n,
		   unsigned int line, struct gline *l);
/* "G64.1" for a code as struct gline stores it (code * 10). */
const char *gcode_gname(int code, char *buf, size_t n);
/* A space or a tab: what separates words. */
bool gcode_is_blank(char ch);

#endif
