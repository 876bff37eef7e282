/* SPDX-License-Identifier: MIT */
/*
 * The tools' one SIGINT/SIGTERM handler: the operator asking a tool to
 * stop. The handler only counts (up to two); the tool looks at the count
 * where it can act on it (between batches, in the runner's progress call)
 * and stops the card there, since a handler cannot call the library.
 */
#include <signal.h>
#include <string.h>

#include "toolcommon.h"

static volatile sig_atomic_t stop_count;

static void on_stop(int sig)
{
	(void)sig;
	if (stop_count < 2)
		stop_count++;
}

void sh2000_tool_catch_stop(enum sh2000_tool_second second)
{
	struct sigaction sa;

	memset(&sa, 0, sizeof(sa));
	sa.sa_handler = on_stop;
	/* one at a time: SIGTERM does not interrupt SIGINT's count */
	sigemptyset(&sa.sa_mask);
	sigaddset(&sa.sa_mask, SIGINT);
	sigaddset(&sa.sa_mask, SIGTERM);
	/* SH2000_SECOND_KILLS: once caught, the default action is back, so a
	 * second signal ends a tool that is busy putting things back */
	sa.sa_flags = second == SH2000_SECOND_KILLS ? (int)SA_RESETHAND : 0;
	stop_count = 0;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
}

int sh2000_tool_stop_asked(void)
{
	return stop_count;
}
