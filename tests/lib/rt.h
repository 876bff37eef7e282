/* SPDX-License-Identifier: MIT */
/*
 * The priorities a real installation gives the parts of a real-time test,
 * so that a busy machine (ordinary processes on every core) does not
 * decide its outcome: a served card stands for a DSP, which no host
 * program ever delays, so its thread runs at SCHED_FIFO above the hosts;
 * a host with a deadline (LinuxCNC's servo thread, a client timing what
 * it learns) runs at SCHED_FIFO below it. Threads and forked processes
 * inherit the caller's policy unless RT_RESET_ON_FORK is asked for.
 *
 * Without the privilege (not root, no CAP_SYS_NICE or RLIMIT_RTPRIO) the
 * test says so once and runs with ordinary scheduling: its timings then
 * hold only on a machine that is not busy.
 */
#ifndef SH2000_TEST_RT_H
#define SH2000_TEST_RT_H

#include "sh2000/sim.h"

#define RT_CARD		50	/* a served card's servo cycles */
#define RT_HOST		40	/* a host with a deadline */

#define RT_RESET_ON_FORK	0x1u	/* children start as ordinary
					   processes */

/* The calling thread at SCHED_FIFO prio: 0, or -errno (then it keeps its
 * policy and the first refusal is printed). */
int rt_fifo(int prio, unsigned int flags);
/* The calling thread back to SCHED_OTHER. */
void rt_other(void);
/* sh2000_sim_server_start() with the server's thread at RT_CARD; the
 * caller's own policy is left as it was. */
int rt_server_start(struct sh2000_sim_server *s);

#endif /* SH2000_TEST_RT_H */
