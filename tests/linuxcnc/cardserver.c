// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * cardserver: simulated cards for the LinuxCNC stage, served like
 * sh2000-sim NAME does, plus what a test needs from outside the server's
 * process: fault injection on command.
 *
 *   cardserver [--start MM] [--index-period MM] CONTROL NAME...
 *
 * Serves sim:NAME for each NAME (one real-time server thread each), every
 * axis powered up at MM (--start; default the model's 300 mm, 300 mm from
 * the home switch) with scale marks every --index-period MM (default the
 * model's 1 mm; 0: a scale without marks), and reads lines from the FIFO
 * CONTROL (created if missing):
 *
 *   jam N AXIS      card N (0 = first NAME) jams axis AXIS
 *   clear N         undo every injection on card N
 *   quit            stop serving, remove the cards, exit 0
 *
 * Prints "ready" once every card is served. SIGINT/SIGTERM quit too.
 */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sh2000/sim.h"

#define MAX_CARDS	4

static volatile sig_atomic_t stop;

static void on_signal(int sig)
{
	(void)sig;
	stop = 1;
}

static int command(struct sh2000_sim_server **s, int n, const char *line)
{
	unsigned int card, axis;

	if (sscanf(line, "jam %u %u", &card, &axis) == 2 && (int)card < n)
		return sh2000_sim_server_inject(s[card], SH2000_INJECT_JAM,
						axis, 0);
	if (sscanf(line, "clear %u", &card) == 1 && (int)card < n)
		return sh2000_sim_server_inject(s[card], SH2000_INJECT_CLEAR,
						0, 0);
	if (!strncmp(line, "quit", 4)) {
		stop = 1;
		return 0;
	}
	fprintf(stderr, "cardserver: unknown command: %s", line);
	return -EINVAL;
}

/* --start MM, --index-period MM: into every axis of cfg; the count of
 * arguments taken, -1 on a bad one. */
static int plant_options(int argc, char **argv, struct sh2000_sim_config *cfg)
{
	int i = 1;
	unsigned int a;

	sh2000_sim_config_default(cfg);
	while (i + 1 < argc && !strncmp(argv[i], "--", 2)) {
		char *end;
		double v = strtod(argv[i + 1], &end);

		if (*end || end == argv[i + 1])
			return -1;
		for (a = 0; a < SH2000_AXES; a++) {
			if (!strcmp(argv[i], "--start"))
				cfg->axis[a].start_mm = v;
			else if (!strcmp(argv[i], "--index-period") && v >= 0)
				cfg->axis[a].index_period_mm = v;
			else
				return -1;
		}
		i += 2;
	}
	return i - 1;
}

int main(int argc, char **argv)
{
	struct sh2000_sim_server *s[MAX_CARDS] = { 0 };
	struct sh2000_sim_config cfg;
	char msg[256], line[128];
	FILE *ctl;
	int n, i, fd, r = 0;
	int opts = plant_options(argc, argv, &cfg);

	if (opts < 0 || argc - opts < 3 || argc - opts - 2 > MAX_CARDS) {
		fprintf(stderr, "usage: cardserver [--start MM] [--index-period MM] CONTROL NAME... (1..%d cards)\n",
			MAX_CARDS);
		return 2;
	}
	argc -= opts;
	argv += opts;
	n = argc - 2;
	{
		/* no SA_RESTART: a signal ends the blocking read below */
		struct sigaction sa = { .sa_handler = on_signal };

		sigaction(SIGINT, &sa, NULL);
		sigaction(SIGTERM, &sa, NULL);
	}
	if (mkfifo(argv[1], 0600) < 0 && errno != EEXIST) {
		fprintf(stderr, "cardserver: %s: %s\n", argv[1], strerror(errno));
		return 1;
	}
	/* read-write: the FIFO never reports end of file between writers */
	fd = open(argv[1], O_RDWR);
	ctl = fd < 0 ? NULL : fdopen(fd, "r");
	if (!ctl) {
		fprintf(stderr, "cardserver: %s: %s\n", argv[1], strerror(errno));
		return 1;
	}
	for (i = 0; i < n; i++) {
		r = sh2000_sim_server_create(&s[i], argv[i + 2], &cfg, 0, msg,
					     sizeof(msg));
		if (r == 0)
			r = sh2000_sim_server_start(s[i]);
		if (r < 0) {
			fprintf(stderr, "cardserver: %s: %s\n", argv[i + 2],
				msg);
			goto out;
		}
	}
	printf("ready\n");
	fflush(stdout);
	while (!stop && fgets(line, sizeof(line), ctl)) {
		if (command(s, n, line) < 0)
			fprintf(stderr, "cardserver: %s failed\n", line);
	}
out:
	for (i = 0; i < n; i++)
		if (s[i])
			sh2000_sim_server_destroy(s[i]);
	fclose(ctl);
	return r < 0 ? 1 : 0;
}
