// SPDX-License-Identifier: MIT
/* Real-time priorities for the tests' real-time parts: see rt.h. */
#include <errno.h>
#include <sched.h>
#include <stdio.h>
#include <string.h>

#include "rt.h"

int rt_fifo(int prio, unsigned int flags)
{
	static int told;
	const struct sched_param p = { .sched_priority = prio };
	int policy = SCHED_FIFO, e;

	if (flags & RT_RESET_ON_FORK)
		policy |= SCHED_RESET_ON_FORK;
	if (sched_setscheduler(0, policy, &p) == 0)
		return 0;
	e = errno;
	if (!told++)
		printf("# SCHED_FIFO not permitted (%s): real-time parts run as ordinary threads; their times hold only on a machine that is not busy\n",
		       strerror(e));
	return -e;
}

void rt_other(void)
{
	const struct sched_param p = { .sched_priority = 0 };

	sched_setscheduler(0, SCHED_OTHER, &p);
}

int rt_server_start(struct sh2000_sim_server *s)
{
	struct sched_param old;
	int policy = sched_getscheduler(0), r;

	/* the server's thread inherits the policy of the thread starting it */
	if (policy < 0 || sched_getparam(0, &old) < 0 ||
	    rt_fifo(RT_CARD, 0) < 0)
		return sh2000_sim_server_start(s);
	r = sh2000_sim_server_start(s);
	sched_setscheduler(0, policy, &old);
	return r;
}
