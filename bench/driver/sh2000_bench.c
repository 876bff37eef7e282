// SPDX-License-Identifier: GPL-2.0 OR MIT
/*
 * Driver benchmark: port cycles per word through /dev/sh2000-N, measured
 * with the GET_COUNTERS ioctl (exact, unlike wall time under emulation).
 * Prints a table; never fails on the figures. Run inside the test VM by
 * `tests/kernel/run --bench`, or by hand on a machine with the modules:
 *
 *	insmod sh2000.ko && insmod sh2000_sim.ko
 *	sh2000_bench /dev/sh2000-0
 *
 * The floor for streaming is 2.0 cycles per word (one data access and one
 * increment; the last word of a transfer needs no increment).
 */
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#include "sh2000_hw.h"
#include "uapi/sh2000.h"

#define RAMB	((long)SH2000_RAM_BYTES)
#define RAMW	((long)SH2000_RAM_WORDS)

static int g_fd;
static uint64_t g_rng = 88172645463325252ULL;

static uint64_t rnd(void)
{
	g_rng ^= g_rng << 13;
	g_rng ^= g_rng >> 7;
	g_rng ^= g_rng << 17;
	return g_rng;
}

struct snap {
	struct sh2000_counters c;
	struct timespec t;
};

static void take(struct snap *s)
{
	if (ioctl(g_fd, SH2000_IOC_GET_COUNTERS, &s->c)) {
		perror("GET_COUNTERS");
		exit(1);
	}
	clock_gettime(CLOCK_MONOTONIC, &s->t);
}

static unsigned long long total(const struct sh2000_counters *c)
{
	return c->clears + c->increments + c->data_reads + c->data_writes;
}

static unsigned long long data(const struct sh2000_counters *c)
{
	return c->data_reads + c->data_writes;
}

static void row(const char *what, const struct snap *a, const struct snap *b,
		double floor)
{
	double words = (double)(data(&b->c) - data(&a->c));
	double cyc = (double)(total(&b->c) - total(&a->c));
	double ns = (double)(b->t.tv_sec - a->t.tv_sec) * 1e9 +
		    (double)(b->t.tv_nsec - a->t.tv_nsec);

	if (floor > 0)
		printf("BENCH %-40s %9.0f %8.4f %8.2f %+7.3f%%\n", what, words,
		       cyc / words, ns / words, (cyc / words / floor - 1) * 100);
	else
		printf("BENCH %-40s %9.0f %8.4f %8.2f %8s\n", what, words,
		       cyc / words, ns / words, "-");
}

static void xfer(int write, void *buf, long len, long off)
{
	long r = write ? pwrite(g_fd, buf, len, off) : pread(g_fd, buf, len, off);

	if (r != len) {
		fprintf(stderr, "transfer at %ld: %ld (%s)\n", off, r,
			strerror(errno));
		exit(1);
	}
}

/* The least cycles from counter position p (-1: unknown) to word t. */
static long seek_cost(long p, long t)
{
	long fwd = (t - p + RAMW) % RAMW;

	if (p < 0)
		return 1 + t;
	return fwd < 1 + t ? fwd : 1 + t;
}

/*
 * The least cost of a seek between two uniformly random words, by the card
 * rules: forward increments (through the wrap), or a clear and t
 * increments, whichever is cheaper.
 */
static double mean_min_seek(void)
{
	double sum = 0;

	for (long p = 0; p < RAMW; p++) {
		for (long t = 0; t < RAMW; t++) {
			long fwd = (t - p + RAMW) % RAMW;

			sum += fwd < 1 + t ? fwd : 1 + t;
		}
	}
	return sum / (double)(RAMW * RAMW);
}

int main(int argc, char **argv)
{
	const char *dev = argc > 1 ? argv[1] : "/dev/sh2000-0";
	long passes = argc > 2 ? atol(argv[2]) : 200;
	long randoms = passes * 100;
	static uint8_t buf[SH2000_RAM_BYTES];
	struct snap a, b;
	double seek_avg, ideal = mean_min_seek(), least = 0;
	long pos;
	int ok = 1;

	g_fd = open(dev, O_RDWR);
	if (g_fd < 0) {
		fprintf(stderr, "%s: %s\n", dev, strerror(errno));
		return 1;
	}
	printf("BENCH %-40s %9s %8s %8s %8s\n", "pattern (" "floor 2.0 for streams)",
	       "words", "cyc/word", "ns/word", "vs floor");

	ioctl(g_fd, SH2000_IOC_FORGET_POSITION);
	take(&a);
	for (long i = 0; i < passes; i++)
		xfer(0, buf, RAMB, 0);
	take(&b);
	row("whole-RAM read (2048-byte pread)", &a, &b, 2.0);
	ok &= (double)(total(&b.c) - total(&a.c)) / (double)(data(&b.c) - data(&a.c)) <= 2.02;

	take(&a);
	for (long i = 0; i < passes; i++)
		xfer(1, buf, RAMB, 0);
	take(&b);
	row("whole-RAM write (2048-byte pwrite)", &a, &b, 2.0);
	ok &= (double)(total(&b.c) - total(&a.c)) / (double)(data(&b.c) - data(&a.c)) <= 2.02;

	take(&a);
	for (long i = 0; i < passes; i++)
		for (long off = 0; off < RAMB; off += 64)
			xfer(0, buf, 64, off);
	take(&b);
	row("whole-RAM read in 64-byte chunks", &a, &b, 2.0);

	take(&a);
	for (long i = 0; i < passes; i++)
		for (long off = 0; off < RAMB; off += 2)
			xfer(1, buf, 2, off);
	take(&b);
	row("whole-RAM write word by word", &a, &b, 2.0);

	take(&a);
	pos = a.c.position == SH2000_POSITION_UNKNOWN ? -1 : (long)a.c.position;
	for (long i = 0; i < randoms; i++) {
		long t = (long)(rnd() % RAMW);

		least += seek_cost(pos, t);
		pos = t;
		xfer(0, buf, 2, 2 * t);
	}
	take(&b);
	row("random-offset single-word read", &a, &b, 0);
	seek_avg = (double)(total(&b.c) - total(&a.c) - (data(&b.c) - data(&a.c))) /
		   (double)randoms;

	take(&a);
	for (long i = 0; i < randoms; i++)
		xfer(1, buf, 2, 2 * (long)(rnd() % RAMW));
	take(&b);
	row("random-offset single-word write", &a, &b, 0);

	take(&a);
	for (long i = 0; i < randoms / 10; i++) {
		ioctl(g_fd, SH2000_IOC_FORGET_POSITION);
		xfer(0, buf, 2, 2 * (long)(rnd() % RAMW));
	}
	take(&b);
	row("random single-word read, position unknown", &a, &b, 0);

	printf("BENCH average seek between random words: %.2f cycles (least possible for this sequence %.2f; mean over all pairs %.2f; clear-only would be %.2f)\n",
	       seek_avg, least / (double)randoms, ideal, 1 + (RAMW - 1) / 2.0);
	printf("BENCH on a real ISA bus at %u ns per port cycle: whole RAM %.3f ms, one random word %.0f us\n",
	       SH2000_PORT_CYCLE_NS, 2.0 * RAMW * SH2000_PORT_CYCLE_NS / 1e6,
	       (seek_avg + 1) * SH2000_PORT_CYCLE_NS / 1e3);
	printf("BENCH whole-RAM transfers within 1%% of the floor: %s\n",
	       ok ? "yes" : "NO");
	close(g_fd);
	return 0;
}
