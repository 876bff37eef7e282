// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * Compensation tables loaded at start (the module's comp= argument,
 * docs/linuxcnc.md "Compensation tables"): before the servo thread runs,
 * each card's table file goes through libsh2000's own loader, the one
 * sh2000ctl comp load uses, so the file's format, its checks and their
 * FILE:LINE messages have one owner. Not real-time: called from
 * rtapi_app_main only.
 */
#include <stdio.h>
#include <string.h>

#include "hsc.h"

int hsc_comp_wanted(const char *path)
{
	return path && path[0] && strcmp(path, "-") != 0;
}

/* The file read and checked against the card's scales and limits by the
 * loader's own check (sh2000_comp_check_file): a bad table on any card
 * fails the load before any card's tables change. */
int hsc_comp_check(struct hsc_card *c, const char *path, char *msg, size_t len)
{
	int r = sh2000_comp_check_file(c->h, path);

	if (r < 0)
		snprintf(msg, len, "%s", sh2000_last_error(c->h));
	return r;
}

int hsc_comp_load(struct hsc_card *c, const char *path, char *msg, size_t len)
{
	int r = sh2000_comp_load_file(c->h, path);

	if (r < 0) {
		snprintf(msg, len, "%s", sh2000_last_error(c->h));
		return r;
	}
	r = sh2000_comp_status(c->h, &c->comp);
	if (r < 0)
		snprintf(msg, len, "%s", sh2000_last_error(c->h));
	return r;
}
