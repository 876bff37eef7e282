/* SPDX-License-Identifier: MIT */
/*
 * The fault matrices' host answer to an error, as the runner's (docs/
 * faults.md, "What the host does with an error"): a card whose state it
 * cannot read gets an emergency stop, a running one a STOP. Without
 * cmocka: lib_matrix and sh2000-kmatrix (linked -static for the VM) use it.
 */
#ifndef SH2000_TEST_HOST_HALT_H
#define SH2000_TEST_HOST_HALT_H

#include "sh2000/sh2000.h"

static inline void host_halt(struct sh2000 *h)
{
	struct sh2000_status st;

	if (sh2000_poll(h, &st) < 0) {
		sh2000_estop(h, 10);
		return;
	}
	if (st.card_state == SH2000_STATE_RUNNING)
		sh2000_stop(h);
}

#endif /* SH2000_TEST_HOST_HALT_H */
