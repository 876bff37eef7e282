// SPDX-License-Identifier: MIT
/*
 * sh2000-share DEVICE [PROCESSES COMMANDS [RECOVER_MS]]: the checks of
 * test_share.c on any card, for the VM suite (tests/kernel, where the
 * device is /dev/sh2000-0 with the card model attached and cmocka has no
 * static library). Prints "ok ...", "FAIL ..." and "info ..." lines; exit
 * status 1 if any check failed.
 *
 *  1. PROCESSES (8) x COMMANDS (10000) mixed commands at once: every one
 *     done, 0 wrong values, 0 errors (a timeout or a lost answer is an
 *     error);
 *  2. a process killed with SIGKILL while it holds the command lock (8
 *     rounds): the next command of another program is answered within
 *     RECOVER_MS (100);
 *  3. a process holding the motion killed with SIGKILL: another claims
 *     the motion and enables an axis within RECOVER_MS.
 */
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/wait.h>

#include "share.h"

static int failed;

static void check(int ok, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

static void check(int ok, const char *fmt, ...)
{
	va_list ap;

	printf("%s ", ok ? "ok" : "FAIL");
	va_start(ap, fmt);
	vprintf(fmt, ap);
	va_end(ap);
	printf("\n");
	failed |= !ok;
}

static void many(const char *dev, unsigned int procs, unsigned int commands)
{
	struct share_tally sum;
	double t0 = share_now_ms();
	int r = share_many(dev, procs, commands, &sum);

	printf("%s share: %u processes x %u mixed commands: %u done in %.1f s (slowest %.1f ms), %u wrong values, %u errors%s%s\n",
	       !r && sum.done == procs * commands && !sum.wrong && !sum.errors ?
	       "ok" : "FAIL", procs, commands, sum.done,
	       (share_now_ms() - t0) / 1e3, sum.max_ms, sum.wrong, sum.errors,
	       sum.errors || r ? ": " : "", sum.msg);
	failed |= r || sum.done != procs * commands || sum.wrong || sum.errors;
}

static void killed_in_command(const char *dev, double limit)
{
	unsigned int held;
	double worst;
	char msg[256];

	if (share_killed_in_command(dev, 8, &held, &worst, msg,
				    sizeof(msg)) < 0) {
		printf("FAIL share: SIGKILL in a command: %s\n", msg);
		failed = 1;
		return;
	}
	check(held > 0 && worst < limit,
	      "share: SIGKILL of a process in a command: the next command answered after at most %.1f ms (limit %.0f ms)",
	      worst, limit);
	printf("info share: %u of 8 processes killed holding the command lock\n",
	       held);
}

static void killed_motion_holder(const char *dev, double limit)
{
	struct sh2000 *h;
	char msg[256];
	int claimed, st, r;
	double t0;
	pid_t p = share_spawn_holder(dev, &claimed);

	h = share_open(dev, msg, sizeof(msg));
	if (p < 0 || !claimed || !h) {
		printf("FAIL share: motion holder: %s\n",
		       h ? "the child could not claim the motion" : msg);
		failed = 1;
		if (p > 0)
			kill(p, SIGKILL);
		sh2000_close(h);
		return;
	}
	r = sh2000_enable(h, 1);
	check(r == -SH2000_EOWNED,
	      "share: enable refused while another program holds the motion (%d: %s)",
	      r, sh2000_last_error(h));
	kill(p, SIGKILL);
	waitpid(p, &st, 0);
	t0 = share_now_ms();
	r = sh2000_claim_motion(h);
	if (!r)
		r = sh2000_enable(h, 1);
	if (!r)
		r = sh2000_disable(h, 1);
	check(!r && share_now_ms() - t0 < limit,
	      "share: SIGKILL of the motion holder: claimed and enabled by another after %.1f ms (limit %.0f ms)",
	      share_now_ms() - t0, limit);
	if (r)
		printf("info share: %s\n", sh2000_last_error(h));
	sh2000_release_motion(h);
	sh2000_close(h);
}

int main(int argc, char **argv)
{
	unsigned int procs = 8, commands = 10000;
	double limit = 100;

	if (argc != 2 && argc != 4 && argc != 5) {
		fprintf(stderr, "usage: sh2000-share DEVICE [PROCESSES COMMANDS [RECOVER_MS]]\n");
		return 2;
	}
	if (argc >= 4) {
		procs = (unsigned int)strtoul(argv[2], NULL, 10);
		commands = (unsigned int)strtoul(argv[3], NULL, 10);
	}
	if (argc == 5)
		limit = strtod(argv[4], NULL);
	setvbuf(stdout, NULL, _IOLBF, 0);
	many(argv[1], procs, commands);
	killed_in_command(argv[1], limit);
	killed_motion_holder(argv[1], limit);
	return failed;
}
