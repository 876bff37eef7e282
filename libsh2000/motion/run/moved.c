// SPDX-License-Identifier: MIT
/*
 * The card rejects a record that moves a disabled axis (REJECT_DISABLED,
 * docs/protocol.md 7.4) and says which record, not which axis: the
 * protocol has no word for it. The runner knows what it sent, so it names
 * the axis: every axis the status shows disabled whose records in this
 * run did not all hold the same position.
 */
#include <stdio.h>
#include <string.h>

#include "moved.h"
#include "sh2000/sh2000_protocol.h"

void sh2000_moved_add(struct sh2000_moved *m,
		      const int32_t counts[SH2000_AXES])
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++) {
		if (!m->have || counts[a] < m->lo[a])
			m->lo[a] = counts[a];
		if (!m->have || counts[a] > m->hi[a])
			m->hi[a] = counts[a];
	}
	m->have = 1;
}

void sh2000_moved_note(const struct sh2000_moved *m,
		       const struct sh2000_status *st,
		       const double scale[SH2000_AXES], char *msg, size_t len)
{
	static const char name[] = SH2000_AXIS_LETTERS;
	size_t n = strlen(msg);
	unsigned int a;

	if (!m->have || !(st->card_faults & SH2000_FAULT_REJECTED) ||
	    st->reject_reason != SH2000_REJECT_DISABLED)
		return;
	for (a = 0; a < SH2000_AXES && n + 1 < len; a++) {
		if ((st->axis[a].state & SH2000_AXIS_ENABLED) ||
		    m->lo[a] == m->hi[a])
			continue;
		snprintf(msg + n, len - n,
			 "; axis %c is disabled and the run's records move it over %.4f..%.4f mm (the card does not drive it: enable it first)",
			 name[a], m->lo[a] / scale[a], m->hi[a] / scale[a]);
		n = strlen(msg);
	}
}
