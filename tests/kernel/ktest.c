// SPDX-License-Identifier: GPL-2.0 OR MIT
/*
 * The in-VM test program of the kernel suite: runs as root in the busybox
 * initramfs against /dev/sh2000-N (and /dev/sh2000-dsp-N for simulated
 * cards) and prints one line per check:
 *
 *	KTEST ok <name>
 *	KTEST FAIL <name>: <first problem> (+N more)
 *
 * Port-cycle expectations come from the model in ktest.h (card rules), never
 * from the driver's own seek code.
 *
 * Usage: ktest stream HOST DSP [--fresh] | multi HOST DSP | signal HOST DSP |
 *	  storm HOST DSP HOST2 | nocard HOST BASE | info HOST BASE |
 *	  sysfs HOST | hold HOST READY GO | twocards H0 D0 H1 D1 |
 *	  dsphold DSP READY GO | latency HOST | interleave HOST |
 *	  hammer HOST [PROCS] | fifo PRIO CMD [ARGS...]
 *
 * fifo runs CMD under SCHED_FIFO at PRIO (busybox has no chrt): the
 * whole-stack stage runs the card model like the DSP it stands for, ahead
 * of the host programs.
 */
#include <fcntl.h>
#include <sched.h>
#include <setjmp.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/uio.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "ktest.h"

/* --- reporting ---------------------------------------------------------- */

static int g_nerr;
static char g_err[600];
static int g_failed_checks;

static void err(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void err(const char *fmt, ...)
{
	va_list ap;

	if (g_nerr++ == 0) {
		va_start(ap, fmt);
		vsnprintf(g_err, sizeof(g_err), fmt, ap);
		va_end(ap);
	}
}

#define EXPECT(cond, ...)			\
	do {					\
		if (!(cond))			\
			err(__VA_ARGS__);	\
	} while (0)

static void begin(void)
{
	g_nerr = 0;
	g_err[0] = 0;
}

static void report(const char *name)
{
	if (g_nerr == 0) {
		printf("KTEST ok %s\n", name);
	} else {
		g_failed_checks++;
		if (g_nerr > 1)
			printf("KTEST FAIL %s: %s (+%d more)\n", name, g_err,
			       g_nerr - 1);
		else
			printf("KTEST FAIL %s: %s\n", name, g_err);
	}
	fflush(stdout);
	begin();
}

static int open_or_die(const char *path, int flags)
{
	int fd = open(path, flags);

	if (fd < 0) {
		printf("KTEST FAIL open %s: %s\n", path, strerror(errno));
		exit(1);
	}
	return fd;
}

/* --- deterministic patterns -------------------------------------------- */

static uint64_t rng_state = 0x9e3779b97f4a7c15ULL;

static uint64_t rnd(void)
{
	uint64_t x = rng_state;

	x ^= x << 13;
	x ^= x >> 7;
	x ^= x << 17;
	rng_state = x;
	return x;
}

static void fill(uint8_t *b, long n, unsigned int seed)
{
	long i;

	for (i = 0; i < n; i++)
		b[i] = (uint8_t)(seed * 131 + i * 7 + (i >> 8) + 1);
}

/* --- the card under test ------------------------------------------------ */

static int g_host = -1, g_dsp = -1;
static struct model g_m;
/* sh2000_sim's own address counter (sysfs), or empty when not simulated */
static char g_hwctr[160];
static int g_hwctr_off;

static long hw_counter(void)
{
	char buf[32];
	FILE *f;
	long v = -1;

	if (!g_hwctr[0])
		return -1;
	f = fopen(g_hwctr, "r");
	if (!f)
		return -1;
	if (fgets(buf, sizeof(buf), f))
		v = strtol(buf, NULL, 0);
	fclose(f);
	return v;
}

static int hw_counter_set(long v)
{
	FILE *f = fopen(g_hwctr, "w");
	int ret;

	if (!f)
		return -1;
	ret = fprintf(f, "%ld\n", v) < 0;
	return fclose(f) || ret ? -1 : 0;
}

static void hw_counter_find(const char *dsp)
{
	struct stat st;

	snprintf(g_hwctr, sizeof(g_hwctr), "/sys/class/sh2000_dsp/%s/counter",
		 strrchr(dsp, '/') + 1);
	if (stat(g_hwctr, &st))
		g_hwctr[0] = 0;
	printf("KTEST info simulated address counter: %s\n",
	       g_hwctr[0] ? g_hwctr : "not available");
}
static uint8_t g_shadow[SH2000_RAM_BYTES];

static void model_sync(void)
{
	struct sh2000_counters c;

	if (get_counters(g_host, &c))
		err("GET_COUNTERS: %s", strerror(errno));
	model_from(&g_m, &c);
}

/* Compare the driver's counters with the model; what names the step. */
static void model_check(const char *what)
{
	struct sh2000_counters c;

	if (get_counters(g_host, &c)) {
		err("%s: GET_COUNTERS: %s", what, strerror(errno));
		return;
	}
	if (c.clears != g_m.clears || c.increments != g_m.incs ||
	    c.data_reads != g_m.reads || c.data_writes != g_m.writes ||
	    (g_m.pos >= 0 ? c.position != (uint32_t)g_m.pos :
			    c.position != SH2000_POSITION_UNKNOWN)) {
		err("%s: counters clr/inc/rd/wr/pos %llu/%llu"
		    "/%llu/%llu/%d, minimal %llu/%llu"
		    "/%llu/%llu/%ld",
		    what, c.clears, c.increments, c.data_reads, c.data_writes,
		    (int)c.position, g_m.clears, g_m.incs, g_m.reads,
		    g_m.writes, g_m.pos);
		model_from(&g_m, &c);	/* report each divergence once */
	}
	/* the card's own counter must be where the driver thinks it is */
	if (g_hwctr[0] && !g_hwctr_off && c.position != SH2000_POSITION_UNKNOWN) {
		long hw = hw_counter();

		if (hw != (long)c.position)
			err("%s: the simulated card's address counter is %ld, the driver says %u",
			    what, hw, c.position);
	}
}

/* pread/pwrite through the host side, checked against model and shadow. */
static long hpread(long off, long len, const char *what)
{
	uint8_t buf[SH2000_RAM_BYTES * 2];
	long exp = model_xfer(&g_m, off, len, 0);
	long r = pread(g_host, buf, len, off);

	if (r != exp)
		err("%s: pread(off %ld, len %ld) = %ld (%s), want %ld", what,
		    off, len, r, r < 0 ? strerror(errno) : "", exp);
	else if (r > 0 && memcmp(buf, g_shadow + off, r))
		err("%s: pread(off %ld, len %ld) data differ", what, off, len);
	model_check(what);
	return r;
}

static long hpwrite(long off, long len, unsigned int seed, const char *what)
{
	uint8_t buf[SH2000_RAM_BYTES * 2];
	long exp = model_xfer(&g_m, off, len, 1);
	long r;

	if (len < 0 || len > (long)sizeof(buf))
		len = 0;
	fill(buf, len, seed);
	r = pwrite(g_host, buf, len, off);
	if (exp < 0 ? !(r == -1 && errno == -exp) : r != exp)
		err("%s: pwrite(off %ld, len %ld) = %ld (%s), want %ld", what,
		    off, len, r, r < 0 ? strerror(errno) : "", exp);
	if (r > 0)
		memcpy(g_shadow + off, buf, r);
	model_check(what);
	return r;
}

/* The card side must hold exactly the shadow. */
static void dsp_check(const char *what)
{
	uint8_t buf[SH2000_RAM_BYTES];
	long r, i;

	if (g_dsp < 0)
		return;
	r = pread(g_dsp, buf, RAMB, 0);
	if (r != RAMB) {
		err("%s: dsp pread = %ld (%s)", what, r, strerror(errno));
		return;
	}
	for (i = 0; i < RAMB; i++) {
		if (buf[i] != g_shadow[i]) {
			err("%s: dsp byte %ld is %#x, host wrote %#x", what, i,
			    buf[i], g_shadow[i]);
			return;
		}
	}
}

/* --- stream semantics and counters -------------------------------------- */

static void t_info(const char *host, unsigned long base, int simulated)
{
	struct sh2000_info in;
	int fd = open_or_die(host, O_RDWR);

	begin();
	memset(&in, 0xa5, sizeof(in));
	if (ioctl(fd, SH2000_IOC_GET_INFO, &in)) {
		err("GET_INFO: %s", strerror(errno));
	} else {
		EXPECT(in.abi_version == SH2000_ABI_VERSION, "abi_version %u",
		       in.abi_version);
		EXPECT(in.ram_bytes == SH2000_RAM_BYTES, "ram_bytes %u",
		       in.ram_bytes);
		EXPECT(in.ram_words == SH2000_RAM_WORDS, "ram_words %u",
		       in.ram_words);
		EXPECT(in.base == base, "base %#x, want %#lx", in.base, base);
		EXPECT(!!(in.flags & SH2000_INFO_SIMULATED) == simulated,
		       "flags %#x", in.flags);
		EXPECT(memchr(in.driver_version, 0, SH2000_VERSION_LEN),
		       "driver_version not NUL-terminated");
		for (int i = 0; i < 8; i++)
			EXPECT(in.reserved[i] == 0, "reserved[%d] = %#x", i,
			       in.reserved[i]);
		if (strstr(host, "sh2000-")) {
			unsigned int n = (unsigned int)atoi(strrchr(host, '-') + 1);

			EXPECT(in.index == n, "index %u for %s", in.index, host);
		}
		printf("KTEST info %s: base %#x index %u flags %#x version '%.16s'\n",
		       host, in.base, in.index, in.flags, in.driver_version);
	}
	report(simulated ? "info: GET_INFO of a simulated card" :
			   "info: GET_INFO of the io= card");
	close(fd);
}

/* docs/driver.md: readv/writev, each segment a separate transfer. */
static void t_vector(void)
{
	uint8_t a[100], b[200], c[6];
	struct iovec iov[3] = { { a, 100 }, { b, 200 }, { c, 6 } };
	long r;

	begin();
	fill(a, 100, 31);
	fill(b, 200, 32);
	fill(c, 6, 33);
	EXPECT(lseek(g_host, 1000, SEEK_SET) == 1000, "lseek");
	model_xfer(&g_m, 1000, 100, 1);
	model_xfer(&g_m, 1100, 200, 1);
	model_xfer(&g_m, 1300, 6, 1);
	r = writev(g_host, iov, 3);
	EXPECT(r == 306, "writev = %ld", r);
	memcpy(g_shadow + 1000, a, 100);
	memcpy(g_shadow + 1100, b, 200);
	memcpy(g_shadow + 1300, c, 6);
	model_check("writev of 3 segments");
	dsp_check("writev");
	memset(a, 0, 100);
	memset(b, 0, 200);
	EXPECT(lseek(g_host, 1000, SEEK_SET) == 1000, "lseek");
	model_xfer(&g_m, 1000, 100, 0);
	model_xfer(&g_m, 1100, 200, 0);
	model_xfer(&g_m, 1300, 6, 0);
	r = readv(g_host, iov, 3);
	EXPECT(r == 306 && !memcmp(a, g_shadow + 1000, 100) &&
	       !memcmp(b, g_shadow + 1100, 200) && !memcmp(c, g_shadow + 1300, 6),
	       "readv = %ld or data differ", r);
	model_check("readv of 3 segments");
	/* an odd segment after a good one: the good one is done */
	iov[1].iov_len = 3;
	EXPECT(lseek(g_host, 0, SEEK_SET) == 0, "lseek");
	model_xfer(&g_m, 0, 100, 0);
	r = readv(g_host, iov, 3);
	EXPECT(r == 100, "readv with an odd second segment = %ld (want 100)", r);
	model_check("readv with an odd segment");
	report("stream: readv/writev move each segment as its own transfer");
}

/* A buffer that ends in an unmapped page: the transfer stops at the fault. */
static void t_efault(void)
{
	uint8_t *two = mmap(NULL, 8192, PROT_READ | PROT_WRITE,
			    MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
	uint8_t *p = two + 4096 - 1024;	/* 1024 good bytes, then a hole */
	long r;

	begin();
	munmap(two + 4096, 4096);
	model_sync();
	hpwrite(0, RAMB, 555, "setup");
	r = pread(g_host, p, RAMB, 0);
	/* docs/driver.md: EFAULT if nothing moved, else the bytes done */
	EXPECT(r == 1024, "pread into a buffer with 1024 good bytes = %ld (%s)",
	       r, r < 0 ? strerror(errno) : "");
	if (r > 0)
		EXPECT(!memcmp(p, g_shadow, r), "partial read data differ");
	fill(p, 1024, 556);
	r = pwrite(g_host, p, RAMB, 0);
	EXPECT(r == 1024, "pwrite from a buffer with 1024 good bytes = %ld (%s)",
	       r, r < 0 ? strerror(errno) : "");
	errno = 0;
	EXPECT(pread(g_host, two + 4096, 64, 0) == -1 && errno == EFAULT,
	       "pread into an unmapped page: errno %d", errno);
	if (r > 0)
		memcpy(g_shadow, p, r);
	dsp_check("after a faulting write: written prefix only");
	EXPECT(lseek(g_host, 0, SEEK_SET) == 0, "lseek");
	r = read(g_host, p, RAMB);
	EXPECT(r == -1 || lseek(g_host, 0, SEEK_CUR) == r,
	       "read() = %ld moved the position to %ld", r,
	       (long)lseek(g_host, 0, SEEK_CUR));
	munmap(two, 4096);
	model_sync();
	report("stream: a buffer ending in an unmapped page: the bytes before the fault, EFAULT if none, card intact");
}

static void t_ioctl_misc(void)
{
	struct sh2000_counters c;

	begin();
	errno = 0;
	EXPECT(ioctl(g_host, _IO(SH2000_IOC_MAGIC, 0x7f)) == -1 &&
	       errno == ENOTTY, "unknown sh2000 ioctl: errno %d, want ENOTTY",
	       errno);
	errno = 0;
	EXPECT(ioctl(g_host, _IOR('x', 1, int), &c) == -1 && errno == ENOTTY,
	       "foreign ioctl: errno %d, want ENOTTY", errno);
	errno = 0;
	EXPECT(ioctl(g_host, SH2000_IOC_GET_COUNTERS, (void *)8) == -1 &&
	       errno == EFAULT, "GET_COUNTERS to a bad pointer: errno %d",
	       errno);
	errno = 0;
	EXPECT(ioctl(g_host, SH2000_IOC_GET_INFO, NULL) == -1 &&
	       errno == EFAULT, "GET_INFO to NULL: errno %d", errno);
	report("ioctl: unknown command ENOTTY, bad pointer EFAULT");
}

static void t_stream_basic(int fresh)
{
	struct sh2000_counters c;
	long off, len, i;
	static const long offs[] = { 0, 1, 2, 3, 4, 5, 7, 8, 9, 15, 16, 17, 31,
				     32, 63, 64, 100, 127, 128, 255, 256, 511,
				     512, 513, 767, 1000, 1008, 1015, 1020,
				     1021, 1022, 1023 };
	static const long lens[] = { 1, 2, 3, 4, 5, 7, 8, 16, 17, 33, 64, 100,
				     255, 256, 511, 512, 1000, 1023, 1024 };
	unsigned int seed = 1;

	if (fresh) {
		begin();
		if (get_counters(g_host, &c))
			err("GET_COUNTERS: %s", strerror(errno));
		EXPECT(c.position == SH2000_POSITION_UNKNOWN &&
		       counters_total(&c) == 0,
		       "fresh card: position %d, %llu cycles", (int)c.position,
		       counters_total(&c));
		report("counters: fresh card has no cycles and an unknown position");
	}
	model_sync();

	begin();
	hpwrite(0, RAMB, seed++, "whole-RAM write");
	hpread(0, RAMB, "whole-RAM read");
	dsp_check("whole-RAM");
	report("stream: whole-RAM write and read back");

	begin();
	for (i = 0; i < RAMW; i++)
		hpwrite(2 * i, 2, seed++, "single-word write");
	for (i = 0; i < RAMW; i++)
		hpread(2 * i, 2, "single-word read");
	for (i = RAMW - 1; i >= 0; i -= 3)
		hpread(2 * i, 2, "single-word read backwards");
	dsp_check("single words");
	report("stream: every word offset, single words");

	begin();
	for (size_t a = 0; a < sizeof(offs) / sizeof(offs[0]); a++) {
		for (size_t b = 0; b < sizeof(lens) / sizeof(lens[0]); b++) {
			off = 2 * offs[a];
			len = 2 * lens[b];
			hpwrite(off, len, seed++, "offset x length write");
			hpread(off, len, "offset x length read");
			hpread(0, 2 * (off / 2 % 5 + 1), "short read at 0");
		}
	}
	dsp_check("offset x length");
	report("stream: offset classes x lengths (incl. crossing the end)");

	/* odd offsets and lengths are refused and cost nothing */
	begin();
	{
		uint8_t buf[64];
		static const long bad[][2] = { { 1, 2 }, { 0, 1 }, { 3, 4 },
					       { 2, 3 }, { 2047, 2 }, { 1, 1 },
					       { 1001, 64 }, { 0, 63 } };

		for (i = 0; i < (long)(sizeof(bad) / sizeof(bad[0])); i++) {
			errno = 0;
			EXPECT(pread(g_host, buf, bad[i][1], bad[i][0]) == -1 &&
			       errno == EINVAL, "pread(off %ld, len %ld): errno %d",
			       bad[i][0], bad[i][1], errno);
			errno = 0;
			EXPECT(pwrite(g_host, buf, bad[i][1], bad[i][0]) == -1 &&
			       errno == EINVAL, "pwrite(off %ld, len %ld): errno %d",
			       bad[i][0], bad[i][1], errno);
		}
		lseek(g_host, 0, SEEK_SET);
		errno = 0;
		EXPECT(read(g_host, buf, 5) == -1 && errno == EINVAL,
		       "read(len 5): errno %d", errno);
		errno = 0;
		EXPECT(write(g_host, buf, 7) == -1 && errno == EINVAL,
		       "write(len 7): errno %d", errno);
		EXPECT(lseek(g_host, 0, SEEK_CUR) == 0,
		       "refused transfer moved the file position");
		/* an odd position is refused by lseek or by the transfer */
		if (lseek(g_host, 3, SEEK_SET) == 3) {
			errno = 0;
			EXPECT(read(g_host, buf, 2) == -1 && errno == EINVAL,
			       "read at odd position 3: errno %d", errno);
			errno = 0;
			EXPECT(write(g_host, buf, 2) == -1 && errno == EINVAL,
			       "write at odd position 3: errno %d", errno);
		} else {
			EXPECT(errno == EINVAL, "lseek(3): errno %d", errno);
		}
		model_check("odd offsets and lengths");
		dsp_check("odd offsets and lengths");
	}
	report("stream: odd offsets and lengths fail with EINVAL, no cycles");

	/* lseek: every whence */
	begin();
	{
		off_t r;
		uint8_t buf[16];

		EXPECT(lseek(g_host, 100, SEEK_SET) == 100, "SEEK_SET 100");
		EXPECT(lseek(g_host, 20, SEEK_CUR) == 120, "SEEK_CUR +20");
		EXPECT(lseek(g_host, -40, SEEK_CUR) == 80, "SEEK_CUR -40");
		EXPECT(lseek(g_host, 0, SEEK_END) == RAMB, "SEEK_END 0");
		EXPECT(lseek(g_host, -2, SEEK_END) == RAMB - 2, "SEEK_END -2");
		EXPECT(lseek(g_host, -RAMB, SEEK_END) == 0, "SEEK_END -2048");
		EXPECT(lseek(g_host, 0, SEEK_SET) == 0, "SEEK_SET 0");
		errno = 0;
		EXPECT(lseek(g_host, -2, SEEK_SET) == -1 && errno == EINVAL,
		       "SEEK_SET -2: errno %d", errno);
		errno = 0;
		EXPECT(lseek(g_host, -2, SEEK_CUR) == -1 && errno == EINVAL,
		       "SEEK_CUR to -2: errno %d", errno);
		errno = 0;
		EXPECT(lseek(g_host, -RAMB - 2, SEEK_END) == -1 &&
		       errno == EINVAL, "SEEK_END -2050: errno %d", errno);
		EXPECT(lseek(g_host, 0, SEEK_CUR) == 0,
		       "failed lseek moved the position");
		for (int w = 5; w < 100; w += 7) {
			if (w == SEEK_DATA || w == SEEK_HOLE)
				continue;
			errno = 0;
			EXPECT(lseek(g_host, 0, w) == -1 && errno == EINVAL,
			       "whence %d: errno %d", w, errno);
		}
		errno = 0;
		EXPECT(lseek(g_host, 0, -1) == -1 && errno == EINVAL,
		       "whence -1: errno %d", errno);
		/* docs/driver.md: any other whence, and results past 2048, EINVAL */
		errno = 0;
		r = lseek(g_host, 10, SEEK_DATA);
		EXPECT(r == -1 && errno == EINVAL, "SEEK_DATA 10 = %ld", (long)r);
		errno = 0;
		r = lseek(g_host, 10, SEEK_HOLE);
		EXPECT(r == -1 && errno == EINVAL, "SEEK_HOLE 10 = %ld", (long)r);
		lseek(g_host, 0, SEEK_SET);
		errno = 0;
		r = lseek(g_host, 4096, SEEK_SET);
		EXPECT(r == -1 && errno == EINVAL, "SEEK_SET 4096 = %ld errno %d",
		       (long)r, errno);
		errno = 0;
		r = lseek(g_host, 2, SEEK_END);
		EXPECT(r == -1 && errno == EINVAL, "SEEK_END +2 = %ld errno %d",
		       (long)r, errno);
		EXPECT(lseek(g_host, 0, SEEK_CUR) == 0,
		       "refused lseek moved the position");
		(void)buf;
		model_check("lseek");
	}
	report("stream: lseek SEEK_SET/CUR/END and invalid whence");

	/* read/write move the file position by what they transferred */
	begin();
	{
		uint8_t buf[RAMB];
		long r;

		EXPECT(lseek(g_host, 0, SEEK_SET) == 0, "SEEK_SET 0");
		for (off = 0; off < RAMB; off += 256) {
			fill(buf, 256, seed);
			model_xfer(&g_m, off, 256, 1);
			r = write(g_host, buf, 256);
			EXPECT(r == 256, "write at %ld = %ld", off, r);
			if (r == 256)
				memcpy(g_shadow + off, buf, 256);
			seed++;
		}
		EXPECT(lseek(g_host, 0, SEEK_CUR) == RAMB, "position after writes");
		model_check("sequential write()");
		errno = 0;
		EXPECT(write(g_host, buf, 2) == -1 && errno == ENOSPC,
		       "write at the end: errno %d", errno);
		EXPECT(read(g_host, buf, 2) == 0, "read at the end");
		EXPECT(lseek(g_host, 0, SEEK_SET) == 0, "SEEK_SET 0");
		for (off = 0; off < RAMB; off += 100) {
			long want = model_xfer(&g_m, off, 100, 0);

			r = read(g_host, buf, 100);
			EXPECT(r == want, "read at %ld = %ld, want %ld", off, r,
			       want);
			if (r > 0)
				EXPECT(!memcmp(buf, g_shadow + off, r),
				       "read at %ld: data differ", off);
		}
		EXPECT(lseek(g_host, 0, SEEK_CUR) == RAMB, "position after reads");
		model_check("sequential read()");
		dsp_check("read/write");
	}
	report("stream: read/write move the position; sequential write()/read() cost the floor");

	/* end of RAM */
	begin();
	{
		uint8_t buf[64];

		EXPECT(pread(g_host, buf, 2, RAMB) == 0, "pread at 2048");
		EXPECT(pread(g_host, buf, 64, RAMB + 2) == 0, "pread at 2050");
		EXPECT(pread(g_host, buf, 0, 10) == 0, "pread len 0");
		errno = 0;
		EXPECT(pwrite(g_host, buf, 2, RAMB) == -1 && errno == ENOSPC,
		       "pwrite at 2048: errno %d", errno);
		errno = 0;
		EXPECT(pwrite(g_host, buf, 64, RAMB + 100) == -1 &&
		       errno == ENOSPC, "pwrite at 2148: errno %d", errno);
		model_check("at the end");
		hpwrite(RAMB - 8, 64, seed++, "write crossing the end");
		hpread(RAMB - 8, 64, "read crossing the end");
		hpwrite(RAMB - 2, 4, seed++, "2 words crossing the end");
		hpread(RAMB - 2, 2048, "long read crossing the end");
		dsp_check("end of RAM");
	}
	report("stream: end of RAM: read 0, write ENOSPC, crossing transfers cut short");
}

static void t_counters(void)
{
	long i, t;

	model_sync();

	begin();
	hpread(0, 2, "setup");
	for (i = 0; i < RAMB; i += 64)
		hpread(i, 64, "sequential 64-byte reads");
	for (i = 0; i < RAMB; i += 2)
		hpwrite(i, 2, (unsigned int)i, "sequential single-word writes");
	for (i = 0; i < 4; i++)
		hpread(0, RAMB, "repeated whole-RAM reads");
	report("counters: sequential streams cost the floor (1 data + 1 increment per word)");

	begin();
	hpread(2 * 500, 2, "to 500");
	hpread(2 * 10, 2, "back to 10 (clear + 10)");
	hpread(2 * 9, 2, "back to 9 (clear + 9)");
	hpread(2 * 9, 2, "same word again (no seek)");
	hpread(2 * 700, 2, "to 700");
	hpread(2 * 699, 2, "back by one (clear + 699 beats 1023 increments)");
	hpread(0, 2, "to 0 (clear)");
	for (i = 1000; i >= 0; i -= 50)
		hpwrite(2 * i, 6, (unsigned int)i, "descending writes");
	report("counters: backward seeks use clear + increments");

	begin();
	hpread(2 * 1023, 2, "to 1023");
	hpread(0, 2, "1023 -> 0: one increment through the wrap");
	hpread(2 * 1023, 2, "to 1023 again");
	hpread(2 * 500, 2, "1023 -> 500: a tie keeps the counter (501 increments)");
	hpread(2 * 1022, 2, "to 1022");
	hpread(2 * 3, 2, "1022 -> 3: clear + 3 beats 5 increments");
	hpread(2 * 1020, 8, "transfer ending at 1023");
	hpread(2 * 1, 2, "1023 -> 1 through the wrap");
	hpwrite(2 * 1016, 16, 77, "write ending at 1023");
	hpwrite(0, 4, 78, "write at 0 after the wrap");
	report("counters: forward through the 1023 -> 0 wrap, ties keep the counter");

	begin();
	for (i = 0; i < 3000; i++) {
		t = (long)(rnd() % RAMW);
		long n = (long)(rnd() % 4) + 1;

		if (rnd() & 1)
			hpread(2 * t, 2 * n, "random read");
		else
			hpwrite(2 * t, 2 * n, (unsigned int)i, "random write");
	}
	dsp_check("random");
	report("counters: random offsets cost the minimum");

	begin();
	if (ioctl(g_host, SH2000_IOC_FORGET_POSITION))
		err("FORGET_POSITION: %s", strerror(errno));
	g_m.pos = -1;
	model_check("after FORGET_POSITION");
	hpread(2 * 300, 2, "first access after forget: clear + 300");
	hpread(2 * 301, 2, "then forward");
	ioctl(g_host, SH2000_IOC_FORGET_POSITION, 0);
	g_m.pos = -1;
	hpread(2 * 301, 2, "same word after forget: clear + 301");
	ioctl(g_host, SH2000_IOC_FORGET_POSITION, 0);
	g_m.pos = -1;
	hpwrite(0, 2, 5, "write at 0 after forget: clear only");
	report("counters: FORGET_POSITION makes the next access clear first");

	if (!g_hwctr[0])
		return;
	begin();
	{
		uint8_t w[2];

		hpread(2 * 5, 2, "to word 5");
		g_hwctr_off = 1;
		EXPECT(hw_counter_set(100) == 0, "cannot move the simulated counter");
		/* the driver trusts its position: one increment, lands on 101 */
		model_xfer(&g_m, 2 * 6, 2, 0);
		EXPECT(pread(g_host, w, 2, 2 * 6) == 2, "pread word 6");
		EXPECT(!memcmp(w, g_shadow + 2 * 101, 2),
		       "with the counter moved to 100, word 6 read %02x%02x, want word 101's %02x%02x",
		       w[1], w[0], g_shadow[203], g_shadow[202]);
		model_check("counter moved behind the driver's back");
		EXPECT(hw_counter() == 101, "card counter %ld, want 101", hw_counter());
		g_hwctr_off = 0;
		EXPECT(ioctl(g_host, SH2000_IOC_FORGET_POSITION) == 0, "FORGET_POSITION");
		g_m.pos = -1;
		hpread(2 * 6, 2, "after FORGET_POSITION word 6 is word 6 again");
	}
	report("counters: a counter moved behind the driver's back is recovered by FORGET_POSITION");
}

static int sysfs_read(const char *dir, const char *name,
		      unsigned long long *v)
{
	char path[256], buf[64];
	FILE *f;

	snprintf(path, sizeof(path), "%s/%s", dir, name);
	f = fopen(path, "r");
	if (!f) {
		snprintf(path, sizeof(path), "%s/counters/%s", dir, name);
		f = fopen(path, "r");
	}
	if (!f)
		return -1;
	if (!fgets(buf, sizeof(buf), f)) {
		fclose(f);
		return -1;
	}
	fclose(f);
	*v = strtoull(buf, NULL, 0);
	return 0;
}

static void t_sysfs(const char *host)
{
	static const char *const names[] = { "clears", "increments",
					     "data_reads", "data_writes" };
	char dir[128];
	struct sh2000_counters c;
	unsigned long long v[4];
	int fd = open_or_die(host, O_RDWR);
	uint8_t buf[64];

	begin();
	snprintf(dir, sizeof(dir), "/sys/class/sh2000/%s", strrchr(host, '/') + 1);
	if (pread(fd, buf, 64, 100) != 64)
		err("pread: %s", strerror(errno));
	if (get_counters(fd, &c))
		err("GET_COUNTERS: %s", strerror(errno));
	for (int i = 0; i < 4; i++)
		if (sysfs_read(dir, names[i], &v[i]))
			err("%s/%s (or counters/%s) missing", dir, names[i],
			    names[i]);
	if (!g_nerr) {
		EXPECT(v[0] == c.clears, "sysfs clears %llu ioctl %llu",
		       v[0], c.clears);
		EXPECT(v[1] == c.increments, "sysfs increments %llu"
		       " ioctl %llu", v[1], c.increments);
		EXPECT(v[2] == c.data_reads, "sysfs data_reads %llu"
		       " ioctl %llu", v[2], c.data_reads);
		EXPECT(v[3] == c.data_writes, "sysfs data_writes %llu"
		       " ioctl %llu", v[3], c.data_writes);
	}
	{
		char path[200], buf[32] = "";
		FILE *f;

		snprintf(path, sizeof(path), "%s/position", dir);
		f = fopen(path, "r");
		if (!f || !fgets(buf, sizeof(buf), f))
			err("%s unreadable", path);
		else if (c.position == SH2000_POSITION_UNKNOWN)
			EXPECT(!strncmp(buf, "unknown", 7), "position '%s', want unknown", buf);
		else
			EXPECT(strtoul(buf, NULL, 0) == c.position,
			       "sysfs position '%s', ioctl %u", buf, c.position);
		if (f)
			fclose(f);
	}
	{
		struct sh2000_info in;
		unsigned long long base = 1, sim = 2;

		if (ioctl(fd, SH2000_IOC_GET_INFO, &in))
			err("GET_INFO: %s", strerror(errno));
		else if (sysfs_read(dir, "base", &base) || sysfs_read(dir, "simulated", &sim))
			err("%s/base or simulated unreadable", dir);
		else
			EXPECT(base == in.base && sim == !!(in.flags & SH2000_INFO_SIMULATED),
			       "sysfs base %#llx simulated %llu, GET_INFO %#x flags %#x",
			       base, sim, in.base, in.flags);
	}
	report("sysfs: counters, position, base and simulated equal the ioctls");
	close(fd);
}

/* --- the card side ------------------------------------------------------ */

static void t_dsp(void)
{
	struct sh2000_counters before, after;
	uint8_t buf[RAMB], got[RAMB];
	uint8_t *map;
	long i;

	model_sync();
	begin();
	hpwrite(0, RAMB, 4242, "host write");
	dsp_check("host write, dsp pread");
	report("dsp: pread sees exactly what the host wrote");

	begin();
	get_counters(g_host, &before);
	fill(buf, RAMB, 999);
	EXPECT(pwrite(g_dsp, buf, RAMB, 0) == RAMB, "dsp pwrite whole RAM: %s",
	       strerror(errno));
	memcpy(g_shadow, buf, RAMB);
	for (i = 0; i < RAMB; i += 2 * 37) {
		buf[0] = (uint8_t)i;
		buf[1] = (uint8_t)(i >> 8);
		EXPECT(pwrite(g_dsp, buf, 2, i) == 2, "dsp pwrite at %ld", i);
		g_shadow[i] = buf[0];
		g_shadow[i + 1] = buf[1];
	}
	get_counters(g_host, &after);
	EXPECT(counters_total(&after) == counters_total(&before),
	       "card-side access cost %llu host port cycles",
	       counters_total(&after) - counters_total(&before));
	hpread(0, RAMB, "host reads dsp data");
	for (i = 0; i < RAMW; i += 13)
		hpread(2 * i, 2, "host reads single dsp words");
	report("dsp: host reads exactly what the card side wrote (no host cycles)");

	begin();
	map = mmap(NULL, RAMB, PROT_READ | PROT_WRITE, MAP_SHARED, g_dsp, 0);
	if (map == MAP_FAILED) {
		err("mmap dsp: %s", strerror(errno));
	} else {
		EXPECT(!memcmp(map, g_shadow, RAMB), "mapping differs from RAM");
		hpwrite(100, 200, 31337, "host write seen in the mapping");
		EXPECT(!memcmp(map, g_shadow, RAMB),
		       "mapping does not show the host write");
		for (i = 0; i < RAMB; i++)
			map[i] = (uint8_t)(i * 3 + 11);
		memcpy(g_shadow, map, RAMB);
		hpread(0, RAMB, "host reads what was stored via the mapping");
		EXPECT(pread(g_dsp, got, RAMB, 0) == RAMB &&
		       !memcmp(got, map, RAMB), "dsp pread differs from mapping");
		munmap(map, RAMB);
	}
	/* the RAM is one page of the mapping; nothing beyond it */
	errno = 0;
	map = mmap(NULL, 8192, PROT_READ, MAP_SHARED, g_dsp, 0);
	EXPECT(map == MAP_FAILED, "mmap of two pages succeeded");
	if (map != MAP_FAILED)
		munmap(map, 8192);
	map = mmap(NULL, 4096, PROT_READ, MAP_SHARED, g_dsp, 4096);
	EXPECT(map == MAP_FAILED, "mmap at page offset 1 succeeded");
	if (map != MAP_FAILED)
		munmap(map, 4096);
	map = mmap(NULL, 4096, PROT_READ | PROT_WRITE, MAP_PRIVATE, g_dsp, 0);
	EXPECT(map == MAP_FAILED, "MAP_PRIVATE mmap succeeded");
	if (map != MAP_FAILED)
		munmap(map, 4096);
	/* the rest of the page is zero and not the RAM */
	map = mmap(NULL, 4096, PROT_READ, MAP_SHARED, g_dsp, 0);
	if (map != MAP_FAILED) {
		hpwrite(0, RAMB, 8080, "whole RAM before looking past it");
		for (i = RAMB; i < 4096; i++)
			if (map[i]) {
				err("mapping byte %ld past the RAM is %#x", i, map[i]);
				break;
			}
		munmap(map, 4096);
	}
	/* the host side has no mmap: it reaches the RAM only by port cycles */
	map = mmap(NULL, 4096, PROT_READ, MAP_SHARED, g_host, 0);
	EXPECT(map == MAP_FAILED, "mmap of the host node succeeded");
	if (map != MAP_FAILED)
		munmap(map, 4096);
	report("dsp: mmap sees host writes and host sees stores; MAP_PRIVATE, other sizes and offsets refused; host node has no mmap");
}

/*
 * The card side stores two patterns into every word through the mapping
 * while the host reads, and the other way round: a word is never torn.
 */
static void t_torn(void)
{
	uint16_t *map = mmap(NULL, 4096, PROT_READ | PROT_WRITE, MAP_SHARED,
			     g_dsp, 0);
	uint16_t w[RAMW];
	long torn = 0, reads = 0;
	pid_t p;
	int status;

	begin();
	if (map == MAP_FAILED) {
		err("mmap: %s", strerror(errno));
		report("dsp: concurrent card-side stores and host transfers never tear a word");
		return;
	}
	for (long i = 0; i < RAMW; i++)
		map[i] = 0x12cd;
	p = fork();
	if (p == 0) {
		volatile uint16_t *v = map;

		alarm(60);
		for (;;)
			for (long i = 0; i < RAMW; i++)
				v[i] = v[i] == 0x12cd ? 0xab34 : 0x12cd;
	}
	for (int it = 0; it < 300; it++) {
		if (pread(g_host, w, RAMB, 0) != RAMB) {
			err("pread: %s", strerror(errno));
			break;
		}
		reads++;
		for (long i = 0; i < RAMW; i++)
			torn += w[i] != 0x12cd && w[i] != 0xab34;
	}
	kill(p, SIGKILL);
	waitpid(p, &status, 0);
	EXPECT(torn == 0, "%ld torn words in %ld whole-RAM host reads", torn, reads);
	torn = 0;

	/* host writes, card side loads */
	p = fork();
	if (p == 0) {
		uint16_t a[RAMW], b[RAMW];

		alarm(60);
		for (long i = 0; i < RAMW; i++) {
			a[i] = 0x00ff;
			b[i] = 0xff00;
		}
		for (;;) {
			pwrite(g_host, a, RAMB, 0);
			pwrite(g_host, b, RAMB, 0);
		}
	}
	for (int it = 0; it < 2000; it++) {
		volatile uint16_t *v = map;

		for (long i = 0; i < RAMW; i++) {
			uint16_t x = v[i];

			torn += x != 0x00ff && x != 0xff00 && x != 0x12cd &&
				x != 0xab34;
		}
	}
	kill(p, SIGKILL);
	waitpid(p, &status, 0);
	EXPECT(torn == 0, "%ld torn words seen by the card side", torn);
	munmap(map, 4096);
	/* the host RAM is now unknown to the shadow: resync */
	pread(g_dsp, g_shadow, RAMB, 0);
	model_sync();
	report("dsp: concurrent card-side stores and host transfers never tear a word");
}

static void t_twocards(const char *h0, const char *d0, const char *h1,
		       const char *d1)
{
	int fh0 = open_or_die(h0, O_RDWR), fd0 = open_or_die(d0, O_RDWR);
	int fh1 = open_or_die(h1, O_RDWR), fd1 = open_or_die(d1, O_RDWR);
	uint8_t a[RAMB], b[RAMB], g[RAMB];

	begin();
	fill(a, RAMB, 1);
	fill(b, RAMB, 2);
	EXPECT(pwrite(fh0, a, RAMB, 0) == RAMB, "write card 0");
	EXPECT(pwrite(fh1, b, RAMB, 0) == RAMB, "write card 1");
	EXPECT(pread(fd0, g, RAMB, 0) == RAMB && !memcmp(g, a, RAMB),
	       "dsp 0 does not hold card 0's data");
	EXPECT(pread(fd1, g, RAMB, 0) == RAMB && !memcmp(g, b, RAMB),
	       "dsp 1 does not hold card 1's data");
	EXPECT(pread(fh0, g, RAMB, 0) == RAMB && !memcmp(g, a, RAMB),
	       "card 0 read back");
	report("dsp: two simulated cards are independent and /dev/sh2000-dsp-N pairs with /dev/sh2000-N");
	close(fh0);
	close(fd0);
	close(fh1);
	close(fd1);
}

/* --- 8 processes on one card -------------------------------------------- */

struct tally {
	long words_read, words_written, errors;
	char msg[160];
};

static void child_region(const char *host, int shared_fd, int k,
			 struct tally *t, long iters)
{
	long lo = k * (RAMB / 8), size = RAMB / 8;
	uint8_t want[RAMB / 8], buf[RAMB / 8];
	int fd = shared_fd >= 0 ? shared_fd : open(host, O_RDWR);

	rng_state = 0x1234567ULL * (k + 1) + (shared_fd >= 0);
	memset(want, 0, sizeof(want));
	if (fd < 0 || pwrite(fd, want, size, lo) != size) {
		snprintf(t->msg, sizeof(t->msg), "child %d setup: %s", k,
			 strerror(errno));
		t->errors++;
		return;
	}
	t->words_written += size / 2;
	for (long it = 0; it < iters; it++) {
		long a = (long)(rnd() % (size / 2)) * 2;
		long n = (long)(rnd() % ((size - a) / 2) + 1) * 2;
		long r;

		for (long i = 0; i < n; i++)
			buf[i] = (uint8_t)(rnd() >> 11);
		r = pwrite(fd, buf, n, lo + a);
		if (r != n) {
			t->errors++;
			snprintf(t->msg, sizeof(t->msg), "child %d pwrite %ld",
				 k, r);
			continue;
		}
		t->words_written += n / 2;
		memcpy(want + a, buf, n);
		r = pread(fd, buf, size, lo);
		if (r != size) {
			t->errors++;
			snprintf(t->msg, sizeof(t->msg), "child %d pread %ld",
				 k, r);
			continue;
		}
		t->words_read += size / 2;
		if (memcmp(buf, want, size)) {
			t->errors++;
			snprintf(t->msg, sizeof(t->msg),
				 "child %d: region data corrupted", k);
		}
	}
	memcpy(buf, want, size);
	if (shared_fd < 0)
		close(fd);
}

static void t_multi(const char *host, int shared)
{
	struct tally *t = mmap(NULL, 8 * sizeof(*t), PROT_READ | PROT_WRITE,
			       MAP_SHARED | MAP_ANONYMOUS, -1, 0);
	struct sh2000_counters before, after;
	int fd = open_or_die(host, O_RDWR);
	pid_t pids[8];
	long rd = 0, wr = 0;
	int k, status, alive = 8;
	time_t start = time(NULL);

	begin();
	memset(t, 0, 8 * sizeof(*t));
	get_counters(fd, &before);
	for (k = 0; k < 8; k++) {
		pids[k] = fork();
		if (pids[k] == 0) {
			child_region(host, shared ? fd : -1, k, &t[k], 300);
			_exit(0);
		}
	}
	while (alive > 0) {
		pid_t p = waitpid(-1, &status, WNOHANG);

		if (p > 0) {
			alive--;
			if (!WIFEXITED(status) || WEXITSTATUS(status))
				err("child %d died, status %#x", (int)p, status);
			continue;
		}
		if (time(NULL) - start > 120) {
			err("deadlock: %d of 8 processes still running after 120 s",
			    alive);
			for (k = 0; k < 8; k++)
				kill(pids[k], SIGKILL);
			while (wait(NULL) > 0)
				;
			break;
		}
		usleep(20000);
	}
	get_counters(fd, &after);
	for (k = 0; k < 8; k++) {
		rd += t[k].words_read;
		wr += t[k].words_written;
		if (t[k].errors)
			err("%s (%ld errors)", t[k].msg, t[k].errors);
	}
	EXPECT(after.data_reads - before.data_reads == (unsigned long long)rd &&
	       after.data_writes - before.data_writes == (unsigned long long)wr,
	       "data cycles %llu/%llu for %ld/%ld words",
	       after.data_reads - before.data_reads,
	       after.data_writes - before.data_writes, rd, wr);
	printf("KTEST info multi: %ld words read, %ld written in %ld s\n", rd,
	       wr, (long)(time(NULL) - start));
	report(shared ? "multi: 8 processes sharing one fd, own regions: data intact, no deadlock, one data cycle per word" :
			"multi: 8 processes with own fds, own regions: data intact, no deadlock, one data cycle per word");
	close(fd);
	munmap(t, 8 * sizeof(*t));
}

/*
 * 8 processes on the same words: 4 write the whole RAM with their own
 * value, 4 read it. Every word read must be a value some writer wrote.
 */
static void t_interleave(const char *host)
{
	struct tally *t = mmap(NULL, 8 * sizeof(*t), PROT_READ | PROT_WRITE,
			       MAP_SHARED | MAP_ANONYMOUS, -1, 0);
	pid_t pids[8];
	int k, status;
	long uniform = 0, reads = 0;

	begin();
	memset(t, 0, 8 * sizeof(*t));
	{
		uint16_t w[RAMW];
		int fd = open_or_die(host, O_RDWR);

		for (long i = 0; i < RAMW; i++)
			w[i] = 0x1111;
		EXPECT(pwrite(fd, w, RAMB, 0) == RAMB, "setup write");
		close(fd);
	}
	for (k = 0; k < 8; k++) {
		pids[k] = fork();
		if (pids[k] == 0) {
			uint16_t w[RAMW];
			int fd = open(host, O_RDWR);

			alarm(120);
			for (int it = 0; it < 150; it++) {
				if (k < 4) {
					for (long i = 0; i < RAMW; i++)
						w[i] = (uint16_t)(0x1111 * (k + 1));
					if (pwrite(fd, w, RAMB, 0) != RAMB)
						t[k].errors++;
					continue;
				}
				if (pread(fd, w, RAMB, 0) != RAMB) {
					t[k].errors++;
					continue;
				}
				t[k].words_read++;
				for (long i = 0; i < RAMW; i++) {
					if (w[i] == 0 || w[i] % 0x1111 ||
					    w[i] / 0x1111 > 4) {
						t[k].errors++;
						snprintf(t[k].msg, sizeof(t[k].msg),
							 "word %ld read %#x, no process wrote it",
							 i, w[i]);
						break;
					}
				}
				long same = 1;

				for (long i = 1; i < RAMW; i++)
					same &= w[i] == w[0];
				t[k].words_written += same;	/* uniform reads */
			}
			_exit(0);
		}
	}
	for (k = 0; k < 8; k++) {
		if (waitpid(pids[k], &status, 0) != pids[k] ||
		    !WIFEXITED(status) || WEXITSTATUS(status))
			err("process %d ended with status %#x (deadlock?)", k, status);
		if (t[k].errors)
			err("process %d: %s (%ld errors)", k,
			    t[k].msg[0] ? t[k].msg : "transfer failed", t[k].errors);
		reads += t[k].words_read;
		uniform += t[k].words_written;
	}
	/* docs/driver.md: a read holds the card mutex for the whole call */
	EXPECT(uniform == reads,
	       "only %ld of %ld whole-RAM reads saw one writer's data (a read is documented atomic)",
	       uniform, reads);
	report("multi: 8 processes on the same words: every whole-RAM read is one writer's data");
	munmap(t, 8 * sizeof(*t));
}

/* Hammer a card until it goes away; ENODEV is the only acceptable end. */
static void t_hammer(const char *host, int procs)
{
	pid_t pids[8];
	int status;

	begin();
	for (int k = 0; k < procs; k++) {
		pids[k] = fork();
		if (pids[k] == 0) {
			uint8_t buf[RAMB];
			struct sh2000_counters c;
			int fd = open(host, O_RDWR);
			long r = 0;

			alarm(60);
			for (long it = 0;; it++) {
				switch (it % 3) {
				case 0: r = pread(fd, buf, RAMB, 0); break;
				case 1: r = pwrite(fd, buf, RAMB, 0); break;
				default: r = ioctl(fd, SH2000_IOC_GET_COUNTERS, &c); break;
				}
				if (r < 0)
					break;
			}
			_exit(errno == ENODEV ? 0 : 10 + (errno & 0x7f));
		}
	}
	for (int k = 0; k < procs; k++) {
		if (waitpid(pids[k], &status, 0) != pids[k] || !WIFEXITED(status) ||
		    WEXITSTATUS(status))
			err("process %d ended with status %#x (want exit on ENODEV)",
			    k, status);
	}
	report("removal: processes busy on the card when it is removed end with ENODEV");
}

/* --- signals ------------------------------------------------------------ */

static volatile sig_atomic_t g_ticks;

static void on_alarm(int sig)
{
	(void)sig;
	g_ticks++;
}

static void t_signal(void)
{
	struct sigaction sa;
	struct itimerval it = { { 0, 200 }, { 0, 200 } };
	struct sh2000_counters before, after;
	uint8_t a[RAMB], b[RAMB], buf[RAMB];
	long partial = 0, eintr = 0, full = 0, words_rd = 0, words_wr = 0;
	long r, calls = 0;
	time_t start;

	model_sync();
	memset(&sa, 0, sizeof(sa));
	sa.sa_handler = on_alarm;	/* no SA_RESTART */
	sigaction(SIGALRM, &sa, NULL);
	fill(a, RAMB, 71);
	fill(b, RAMB, 72);

	begin();
	EXPECT(pwrite(g_host, a, RAMB, 0) == RAMB, "setup write");
	get_counters(g_host, &before);
	setitimer(ITIMER_REAL, &it, NULL);
	start = time(NULL);
	while (time(NULL) - start < 6 && partial + eintr < 200) {
		int wr = calls++ & 1;

		if (wr) {
			/* b over a: the card must hold b up to r, a after it */
			r = pwrite(g_host, b, RAMB, 0);
		} else {
			memset(buf, 0, sizeof(buf));
			r = pread(g_host, buf, RAMB, 0);
		}
		if (r < 0) {
			if (errno != EINTR)
				err("transfer failed: %s", strerror(errno));
			eintr++;
		} else if (r < RAMB) {
			partial++;
			/* docs/driver.md: stops between chunks of 64 words */
			EXPECT(r % 128 == 0, "partial count %ld is not a whole number of 64-word chunks", r);
		} else {
			full++;
		}
		if (r > 0 && wr)
			words_wr += r / 2;
		if (r > 0 && !wr) {
			words_rd += r / 2;
			if (memcmp(buf, a, r))
				err("partial read of %ld bytes returned wrong data", r);
		}
		if (r > 0 && wr) {
			/* check the card side: b up to r, a after it */
			uint8_t d[RAMB];

			pread(g_dsp, d, RAMB, 0);
			if (memcmp(d, b, r) || memcmp(d + r, a + r, RAMB - r))
				err("write reported %ld bytes, card holds something else", r);
			/* restore a for the next round */
			pwrite(g_dsp, a, RAMB, 0);
		}
	}
	memset(&it, 0, sizeof(it));
	setitimer(ITIMER_REAL, &it, NULL);
	get_counters(g_host, &after);
	EXPECT(after.data_reads - before.data_reads == (unsigned long long)words_rd &&
	       after.data_writes - before.data_writes == (unsigned long long)words_wr,
	       "data cycles %llu/%llu but transfers reported %ld/%ld words",
	       after.data_reads - before.data_reads,
	       after.data_writes - before.data_writes, words_rd, words_wr);
	printf("KTEST info signal: %ld transfers, %ld full, %ld partial, %ld EINTR, %ld signals\n",
	       calls, full, partial, eintr, (long)g_ticks);
	report("signal: interrupted transfers report what they did, data intact");

	begin();
	EXPECT(partial + eintr > 0,
	       "no transfer stopped early in %ld whole-RAM transfers with a 200 us timer",
	       calls);
	report("signal: a pending signal stops a long transfer early");
	signal(SIGALRM, SIG_DFL);
	model_sync();
}

/* --- randomised syscall storm ------------------------------------------- */

static sigjmp_buf g_jmp;

static void on_segv(int sig)
{
	siglongjmp(g_jmp, sig);
}

static void *bad_ptr(uint8_t *good)
{
	switch (rnd() % 6) {
	case 0: return NULL;
	case 1: return (void *)(uintptr_t)(rnd() & 0xfff);
	case 2: return (void *)0xffff888000000000ULL;	/* kernel direct map */
	case 3: return (void *)0xffffffff81000000ULL;	/* kernel text */
	case 4: return good + 4096 * 64;		/* unmapped after buf */
	default: return (void *)(uintptr_t)rnd();
	}
}

static unsigned long rnd_cmd(void)
{
	static const unsigned long known[] = { SH2000_IOC_GET_INFO,
					       SH2000_IOC_GET_COUNTERS,
					       SH2000_IOC_FORGET_POSITION };
	unsigned long cmd;
	unsigned int type;

	switch (rnd() % 4) {
	case 0:
		return known[rnd() % 3];
	case 1:	/* our magic, any number, direction and size */
		return _IOC(rnd() % 4, SH2000_IOC_MAGIC, rnd() % 16,
			    rnd() % 0x3fff);
	case 2:	/* a known number with the wrong size or direction */
		return _IOC(rnd() % 4, SH2000_IOC_MAGIC, rnd() % 3,
			    rnd() % 128);
	default:
		cmd = (unsigned long)(uint32_t)rnd();
		type = _IOC_TYPE(cmd);
		/*
		 * Leave out what the VFS handles for every file (freeze,
		 * clone, FIO*, terminal ioctls): they act on the filesystem
		 * holding /dev, not on the driver.
		 */
		if (type == 'X' || type == 'f' || type == 'T' || type == 0x94 ||
		    type == 0x12 || type == 0x15)
			cmd = _IOC(_IOC_DIR(cmd), 'x', _IOC_NR(cmd),
				   _IOC_SIZE(cmd));
		return cmd;
	}
}

static long rnd_off(void)
{
	switch (rnd() % 8) {
	case 0: return -(long)(rnd() % 5000);
	case 1: return (long)(rnd() % 5000);
	case 2: return (long)(rnd() % 4096) | 1;
	case 3: return RAMB - 2 * (long)(rnd() % 4);
	case 4: return (long)(rnd() >> 2);
	default: return 2 * (long)(rnd() % RAMW);
	}
}

static long rnd_len(void)
{
	switch (rnd() % 6) {
	case 0: return (long)(rnd() % 4096);
	case 1: return (long)(rnd() % 8);
	case 2: return RAMB;
	case 3: return (long)(rnd() % 64) * 2;
	default: return 2 * (long)(rnd() % 1200);
	}
}

struct storm_stats {
	long xfer_ok;		/* transfers that moved data */
	long ok;		/* other calls that succeeded */
	long err[134];		/* failures by errno */
};

static long storm_worker(const char *host, const char *dsp, const char *host2,
			 long ops, uint64_t seed, struct storm_stats *st)
{
	static uint8_t buf[8192] __attribute__((aligned(4096)));
	const char *paths[3] = { host, dsp, host2 };
	int fds[6];
	long done, weird = 0;
	struct sigaction sa;

	memset(&sa, 0, sizeof(sa));
	sa.sa_handler = on_segv;
	sigaction(SIGSEGV, &sa, NULL);
	sigaction(SIGBUS, &sa, NULL);
	rng_state = seed;
	for (int i = 0; i < 6; i++)
		fds[i] = open(paths[i % 3], i < 3 ? O_RDWR : O_RDONLY);
	for (done = 0; done < ops; done++) {
		int slot = (int)(rnd() % 6), fd = fds[slot];
		uint8_t *p = rnd() % 8 ? buf : bad_ptr(buf);
		long off = rnd_off(), len = rnd_len(), r = 0;
		unsigned int op = (unsigned int)(rnd() % 12);

		if (len > (long)sizeof(buf) && p == buf)
			len = sizeof(buf);
		errno = 0;
		switch (op) {
		case 0:
		case 1:
			r = pread(fd, p, len, off);
			break;
		case 2:
		case 3:
			r = pwrite(fd, p, len, off);
			break;
		case 4:
			r = read(fd, p, len);
			break;
		case 5:
			r = write(fd, p, len);
			break;
		case 6:
		case 7:
			r = lseek(fd, off, (int)(rnd() % 8) - 1);
			break;
		case 8:
		case 9: {
			unsigned long arg;

			switch (rnd() % 4) {
			case 0: arg = (unsigned long)buf; break;
			case 1: arg = (unsigned long)bad_ptr(buf); break;
			case 2: arg = (unsigned long)(buf + 4096 - rnd() % 64); break;
			default: arg = (unsigned long)rnd(); break;
			}
			r = ioctl(fd, rnd_cmd(), arg);
			break;
		}
		case 10: {
			size_t mlen = (size_t)(rnd() % 3 + 1) * 1024;
			off_t moff = (off_t)(rnd() % 3) * 4096;
			volatile int prot = rnd() & 1 ? PROT_READ : PROT_READ | PROT_WRITE;
			uint8_t *m = mmap(NULL, mlen, prot,
					  rnd() & 1 ? MAP_SHARED : MAP_PRIVATE,
					  fd, moff);

			if (m != MAP_FAILED) {
				if (sigsetjmp(g_jmp, 1) == 0) {
					volatile uint8_t x = m[rnd() % mlen];

					(void)x;
					if (prot & PROT_WRITE)
						m[rnd() % mlen] = (uint8_t)rnd();
				} else {
					weird++;
				}
				munmap(m, mlen);
			}
			break;
		}
		default:
			close(fd);
			fds[slot] = open(paths[slot % 3],
					 rnd() & 1 ? O_RDWR : O_RDONLY);
			break;
		}
		if (op >= 10)
			continue;
		if (r < 0)
			st->err[errno > 0 && errno < 134 ? errno : 0]++;
		else if (op < 6 && r > 0)
			st->xfer_ok++;
		else
			st->ok++;
	}
	for (int i = 0; i < 6; i++)
		close(fds[i]);
	return weird;
}

static void t_storm(const char *host, const char *dsp, const char *host2,
		    long ops, unsigned long long seed)
{
	pid_t p[2];
	int status;
	time_t start = time(NULL);
	uint8_t a[RAMB], b[RAMB];
	int fd, dfd;
	struct storm_stats *st = mmap(NULL, 2 * sizeof(*st),
				      PROT_READ | PROT_WRITE,
				      MAP_SHARED | MAP_ANONYMOUS, -1, 0);
	long xfer = 0, okc = 0, e[134] = { 0 }, fails = 0;

	begin();
	memset(st, 0, 2 * sizeof(*st));
	for (int k = 0; k < 2; k++) {
		p[k] = fork();
		if (p[k] == 0) {
			storm_worker(host, dsp, host2, ops / 2,
				     0xdeadbeefULL * seed + (uint64_t)k * 7919,
				     &st[k]);
			_exit(0);
		}
	}
	for (int k = 0; k < 2; k++) {
		if (waitpid(p[k], &status, 0) != p[k] || !WIFEXITED(status) ||
		    WEXITSTATUS(status))
			err("storm worker %d ended with status %#x", k, status);
	}
	for (int k = 0; k < 2; k++) {
		xfer += st[k].xfer_ok;
		okc += st[k].ok;
		for (int i = 0; i < 134; i++) {
			e[i] += st[k].err[i];
			fails += st[k].err[i];
		}
	}
	printf("KTEST info storm (seed %llu): %ld operations in %ld s: %ld transfers moved data, %ld other calls ok, %ld failed (EINVAL %ld, EFAULT %ld, ENOSPC %ld, ENOTTY %ld, EBADF %ld, ENODEV %ld, other %ld)\n",
	       seed, ops, (long)(time(NULL) - start), xfer, okc, fails, e[EINVAL],
	       e[EFAULT], e[ENOSPC], e[ENOTTY], e[EBADF], e[ENODEV],
	       fails - e[EINVAL] - e[EFAULT] - e[ENOSPC] - e[ENOTTY] -
	       e[EBADF] - e[ENODEV]);
	/* a storm that only bounces off argument checks tests little */
	EXPECT(xfer > ops / 10 && e[EINVAL] && e[EFAULT] && e[ENOSPC] &&
	       e[ENOTTY], "storm too shallow: %ld transfers moved data", xfer);
	munmap(st, 2 * sizeof(*st));
	/* the card still works and is consistent */
	fd = open(host, O_RDWR);
	dfd = open(dsp, O_RDWR);
	fill(a, RAMB, 4711);
	EXPECT(fd >= 0 && dfd >= 0, "reopen after the storm: %s", strerror(errno));
	EXPECT(pwrite(fd, a, RAMB, 0) == RAMB, "write after the storm");
	EXPECT(pread(fd, b, RAMB, 0) == RAMB && !memcmp(a, b, RAMB),
	       "read back after the storm");
	EXPECT(pread(dfd, b, RAMB, 0) == RAMB && !memcmp(a, b, RAMB),
	       "card side after the storm");
	report("storm: randomised syscalls (offsets, lengths, whence, ioctls, bad pointers, mmap)");
	close(fd);
	close(dfd);
}

/* --- the real-card path without a card ---------------------------------- */

static void t_nocard(const char *host)
{
	uint8_t buf[RAMB];
	long i, bad = 0;

	g_host = open_or_die(host, O_RDWR);
	g_dsp = -1;
	model_sync();
	begin();
	EXPECT(model_xfer(&g_m, 0, RAMB, 0) == RAMB &&
	       pread(g_host, buf, RAMB, 0) == RAMB, "pread: %s", strerror(errno));
	for (i = 0; i < RAMB; i++)
		bad += buf[i] != 0xff;
	EXPECT(bad == 0, "%ld bytes of the floating bus are not 0xff", bad);
	model_check("read without a card");
	report("nocard: whole-RAM read returns 0xFFFF words");

	begin();
	fill(buf, RAMB, 3);
	EXPECT(model_xfer(&g_m, 0, RAMB, 1) == RAMB &&
	       pwrite(g_host, buf, RAMB, 0) == RAMB, "pwrite: %s", strerror(errno));
	for (i = 0; i < 200; i++) {
		long w = (long)(rnd() % RAMW);

		model_xfer(&g_m, 2 * w, 2, i & 1);
		if (i & 1) {
			EXPECT(pwrite(g_host, buf, 2, 2 * w) == 2, "pwrite word");
		} else {
			buf[0] = buf[1] = 0;
			EXPECT(pread(g_host, buf, 2, 2 * w) == 2 &&
			       buf[0] == 0xff && buf[1] == 0xff,
			       "word %ld reads %#x%02x", w, buf[1], buf[0]);
		}
	}
	model_check("random access without a card");
	report("nocard: writes go nowhere without harm; port cycles as the model says");
	close(g_host);
}

/* --- removal while open -------------------------------------------------- */

static void wait_file(const char *path)
{
	struct stat st;

	for (int i = 0; i < 6000 && stat(path, &st); i++)
		usleep(10000);
}

static void t_hold(const char *host, const char *ready, const char *go,
		   const char *name)
{
	int fd = open_or_die(host, O_RDWR);
	uint8_t buf[64] = { 0 };
	struct sh2000_info c;
	long r;

	EXPECT(pread(fd, buf, 64, 0) == 64, "pread before removal");
	close(open(ready, O_CREAT | O_WRONLY, 0600));
	wait_file(go);
	begin();
	/* docs/driver.md: every operation ENODEV, checked before EINVAL */
#define GONE(call, what)						\
	do {								\
		errno = 0;						\
		r = (long)(call);					\
		EXPECT(r == -1 && errno == ENODEV,			\
		       "%s after removal = %ld (%s)", what, r,		\
		       strerror(errno));				\
	} while (0)
	GONE(pread(fd, buf, 64, 0), "pread");
	GONE(pwrite(fd, buf, 64, 0), "pwrite");
	GONE(read(fd, buf, 64), "read");
	GONE(write(fd, buf, 64), "write");
	GONE(pread(fd, buf, 3, 1), "odd pread");
	GONE(ioctl(fd, SH2000_IOC_GET_COUNTERS, &c), "GET_COUNTERS");
	GONE(ioctl(fd, SH2000_IOC_GET_INFO, &c), "GET_INFO");
	GONE(ioctl(fd, SH2000_IOC_FORGET_POSITION), "FORGET_POSITION");
	GONE(lseek(fd, 2, SEEK_SET), "lseek");
#undef GONE
	EXPECT(close(fd) == 0, "close after removal: %s", strerror(errno));
	report(name);
}

/* Keep the card side open (and mapped) while the sim module is removed. */
static void t_dsphold(const char *dsp, const char *ready, const char *go)
{
	int fd = open_or_die(dsp, O_RDWR);
	uint8_t *m = mmap(NULL, RAMB, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
	uint8_t buf[16];
	long r;

	close(open(ready, O_CREAT | O_WRONLY, 0600));
	wait_file(go);
	begin();
	errno = 0;
	r = pread(fd, buf, 16, 0);
	printf("KTEST info card side after rmmod attempt: pread = %ld (%s)\n", r,
	       strerror(errno));
	if (m != MAP_FAILED) {
		m[0] = 1;	/* must not touch freed memory */
		munmap(m, RAMB);
	}
	EXPECT(close(fd) == 0, "close: %s", strerror(errno));
	report("removal: card-side file and mapping held across an rmmod attempt");
}

/*
 * --- latency: a figure for real hardware; not run in the QEMU suite, where
 * TCG timer noise (tens of ms) swamps it ---------------------------------
 */

static long wakeup_latency_us(long ms)
{
	struct timespec next, now;
	long worst = 0, d;
	struct timespec end;

	clock_gettime(CLOCK_MONOTONIC, &end);
	end.tv_sec += ms / 1000;
	end.tv_nsec += (ms % 1000) * 1000000L;
	if (end.tv_nsec >= 1000000000L) {
		end.tv_sec++;
		end.tv_nsec -= 1000000000L;
	}
	clock_gettime(CLOCK_MONOTONIC, &next);
	for (;;) {
		next.tv_nsec += 500000;
		if (next.tv_nsec >= 1000000000L) {
			next.tv_sec++;
			next.tv_nsec -= 1000000000L;
		}
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
		clock_gettime(CLOCK_MONOTONIC, &now);
		d = (now.tv_sec - next.tv_sec) * 1000000L +
		    (now.tv_nsec - next.tv_nsec) / 1000;
		if (d > worst)
			worst = d;
		if (now.tv_sec > end.tv_sec ||
		    (now.tv_sec == end.tv_sec && now.tv_nsec > end.tv_nsec))
			return worst;
	}
}

static void t_latency(const char *host)
{
	cpu_set_t one;
	struct sched_param sp = { .sched_priority = 50 };
	long idle, busy;
	pid_t hog;

	CPU_ZERO(&one);
	CPU_SET(0, &one);
	sched_setaffinity(0, sizeof(one), &one);
	if (sched_setscheduler(0, SCHED_FIFO, &sp)) {
		printf("KTEST info latency: SCHED_FIFO unavailable: %s\n",
		       strerror(errno));
		return;
	}
	idle = wakeup_latency_us(1000);
	hog = fork();
	if (hog == 0) {
		static uint8_t buf[SH2000_RAM_BYTES];
		struct sched_param nsp = { 0 };
		int fd = open(host, O_RDWR);

		sched_setscheduler(0, SCHED_OTHER, &nsp);
		for (;;) {
			pread(fd, buf, RAMB, 0);
			pwrite(fd, buf, RAMB, 0);
		}
	}
	usleep(50000);
	busy = wakeup_latency_us(2000);
	kill(hog, SIGKILL);
	waitpid(hog, NULL, 0);
	printf("KTEST info latency (TCG timers, indicative only): worst wakeup of a SCHED_FIFO task on the same CPU: %ld us idle, %ld us while another task streams whole-RAM transfers\n",
	       idle, busy);
}

int main(int argc, char **argv)
{
	setvbuf(stdout, NULL, _IOLBF, 0);
	if (argc < 3) {
		fprintf(stderr, "usage: see the comment at the top of ktest.c\n");
		return 2;
	}
	if (!strcmp(argv[1], "stream") && argc >= 4) {
		g_host = open_or_die(argv[2], O_RDWR);
		g_dsp = open_or_die(argv[3], O_RDWR);
		hw_counter_find(argv[3]);
		t_stream_basic(argc > 4 && !strcmp(argv[4], "--fresh"));
		t_counters();
		t_dsp();
		t_torn();
		t_efault();
		t_vector();
		t_ioctl_misc();
	} else if (!strcmp(argv[1], "multi") && argc >= 3) {
		t_multi(argv[2], 0);
		t_multi(argv[2], 1);
	} else if (!strcmp(argv[1], "signal") && argc >= 4) {
		g_host = open_or_die(argv[2], O_RDWR);
		g_dsp = open_or_die(argv[3], O_RDWR);
		t_signal();
	} else if (!strcmp(argv[1], "storm") && argc >= 5) {
		t_storm(argv[2], argv[3], argv[4],
			argc > 5 ? atol(argv[5]) : 100000,
			argc > 6 ? strtoull(argv[6], NULL, 0) : 1);
	} else if (!strcmp(argv[1], "nocard")) {
		t_nocard(argv[2]);
	} else if (!strcmp(argv[1], "info") && argc >= 4) {
		t_info(argv[2], strtoul(argv[3], NULL, 0),
		       strtoul(argv[3], NULL, 0) == 0);
	} else if (!strcmp(argv[1], "interleave")) {
		t_interleave(argv[2]);
	} else if (!strcmp(argv[1], "hammer")) {
		t_hammer(argv[2], argc > 3 ? atoi(argv[3]) : 4);
	} else if (!strcmp(argv[1], "latency")) {
		t_latency(argv[2]);
	} else if (!strcmp(argv[1], "sysfs")) {
		t_sysfs(argv[2]);
	} else if (!strcmp(argv[1], "hold") && argc >= 5) {
		t_hold(argv[2], argv[3], argv[4], argc > 5 ? argv[5] :
		       "removal: I/O on a file whose simulated card was removed fails cleanly");
	} else if (!strcmp(argv[1], "dsphold") && argc >= 5) {
		t_dsphold(argv[2], argv[3], argv[4]);
	} else if (!strcmp(argv[1], "fifo") && argc >= 4) {
		struct sched_param sp = { .sched_priority = atoi(argv[2]) };

		if (sched_setscheduler(0, SCHED_FIFO, &sp)) {
			fprintf(stderr, "ktest fifo: sched_setscheduler: %s\n",
				strerror(errno));
			return 126;
		}
		execvp(argv[3], &argv[3]);
		fprintf(stderr, "ktest fifo: %s: %s\n", argv[3], strerror(errno));
		return 127;
	} else if (!strcmp(argv[1], "twocards") && argc >= 6) {
		t_twocards(argv[2], argv[3], argv[4], argv[5]);
	} else {
		fprintf(stderr, "ktest: unknown command %s\n", argv[1]);
		return 2;
	}
	return g_failed_checks ? 1 : 0;
}
