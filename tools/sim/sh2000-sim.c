/* SPDX-License-Identifier: MIT */
/*
 * sh2000-sim: serve a simulated SH-2000TH card.
 *
 *   sh2000-sim [options] NAME          card for `sim:NAME` devices, over
 *                                      POSIX shared memory /sh2000-NAME
 *   sh2000-sim [options] --attach PATH card model on the DSP side of a
 *                                      kernel sh2000_sim card
 *                                      (/dev/sh2000-dsp-N) or on any file
 *                                      of 2048+ bytes (tests)
 *
 * Runs in the foreground until SIGINT/SIGTERM/SIGHUP; see sh2000-sim(1). Kept to
 * libc + libsh2000 so that it links with -static for the VM's initramfs.
 */
#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <sched.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <sh2000/sim.h>

#include "toolcommon.h"

/* the dual-port RAM a served name or file holds, in bytes */
#define RAM_BYTES (2u * SH2000_DPRAM_WORDS)

#ifndef SH2000_TOOLS_VERSION
#define SH2000_TOOLS_VERSION "0.0.0"
#endif

/*
 * The SCHED_FIFO priority a real-time card takes by default: a real card's
 * DSP never waits for the PC, and an ordinary process on a busy desktop
 * wakes milliseconds late now and then (tens of ms with a busy process per
 * core), which drains a LinuxCNC queue of 10 ms. Below LinuxCNC's servo
 * thread (rtapi_app's threads take 90s), above everything ordinary.
 */
#define SIM_PRIORITY	60

/* Set by the signal handlers; the server only needs a flag. */
static volatile sig_atomic_t stop_requested;
static struct sh2000_sim_server *volatile served;

static void on_signal(int sig)
{
	(void)sig;
	stop_requested = 1;
	if (served)
		sh2000_sim_server_stop(served);
}

static int install_signals(void)
{
	struct sigaction sa;

	memset(&sa, 0, sizeof(sa));
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	/* no SA_RESTART: the sleeps return EINTR and see the flag */
	/* SIGHUP: the terminal it runs in was closed; clean up as well */
	if (sigaction(SIGINT, &sa, NULL) < 0 ||
	    sigaction(SIGTERM, &sa, NULL) < 0 ||
	    sigaction(SIGHUP, &sa, NULL) < 0)
		return -errno;
	signal(SIGPIPE, SIG_IGN);
	return 0;
}

static void usage(FILE *f)
{
	fprintf(f,
"Usage: sh2000-sim [OPTION]... NAME\n"
"       sh2000-sim [OPTION]... --attach PATH\n"
"Serve a simulated SH-2000TH card until SIGINT, SIGTERM or SIGHUP.\n"
"\n"
"  NAME               serve the card for the device string sim:NAME\n"
"                     (shared memory /sh2000-NAME; a stale object left by a\n"
"                     dead server is replaced, a live server's name refused)\n"
"  -a, --attach PATH  run the card model on PATH instead: the DSP side of a\n"
"                     kernel simulated card (/dev/sh2000-dsp-N) or any file\n"
"                     of at least 2048 bytes\n"
"  -F, --free-run     run servo cycles back to back (faster than real time)\n"
"                     instead of one per servo period\n"
"  -c, --clock-ppm N  the card's oscillator is off by N ppm (a real number,\n"
"                     -100000..100000): a servo period lasts\n"
"                     nominal * (1 + N * 1e-6) of real time; N > 0 is a slow\n"
"                     card (default 0)\n"
"  -r, --ready-fd FD  write \"ready\\n\" to file descriptor FD once serving,\n"
"                     then close it\n"
"  -p, --priority N   the SCHED_FIFO priority the card's servo loop takes\n"
"                     when the system permits it (1..99, default %d; 0: none);\n"
"                     when it does not, a note on stderr says so\n"
"  -q, --quiet        print nothing on stdout (errors still go to stderr)\n"
"  --mass KG          every axis' moving mass (default 2)\n"
"  --friction NS_PER_M  every axis' viscous friction, N/(m/s) (default 20)\n"
"  -g, --gantry A+B[:C]  axes A and B drive one beam (a gantry: its yaw\n"
"                     stiffness, the beam's and the carriage's mass as\n"
"                     docs/cardmodel.md gives them), the carriage on axis C\n"
"                     along it (default: the first other axis; '-': none,\n"
"                     it stays at side A); e.g. y+z\n"
"  --geometry KIND    the machine's geometric errors (docs/cardmodel.md\n"
"                     \"Geometry\"): none (a perfect machine, the default)\n"
"                     or default (the card model's default errors: about\n"
"                     10 um of pitch error over 300 mm, 50 urad squareness)\n"
"  --tool-file PATH   when stopped, write the tool's true position (the\n"
"                     simulated interferometer, mm, machine frame) to PATH:\n"
"                     one line \"tool X Y Z A\"\n"
"  -h, --help         this help\n"
"  -V, --version      versions of the tool, the library and the protocol\n"
"\n"
"Prints where it serves, then a line \"ready\" on stdout (unless --quiet).\n"
"Exit status: 0 stopped by a signal, 1 failure while serving, 2 usage\n"
"error, 3 the name or PATH cannot be served.\n", SIM_PRIORITY);
}

static void print_ready(int quiet, int ready_fd)
{
	if (!quiet) {
		printf("ready\n");
		fflush(stdout);
	}
	if (ready_fd >= 0) {
		static const char r[] = "ready\n";
		ssize_t n;

		do
			n = write(ready_fd, r, sizeof(r) - 1);
		while (n < 0 && errno == EINTR);
		close(ready_fd);
	}
}

/* How the card is served: the options that apply to both ways. */
struct serve_opts {
	unsigned int flags;
	double ppm;
	int quiet, ready_fd;
	int priority;		/* SCHED_FIFO priority to take, 0 none */
	/* the machine behind the card: every axis' plant */
	struct sh2000_sim_config cfg;
	int gantry_on;			/* --gantry: two axes on one beam */
	struct sh2000_gantry_config gantry;
	int geometry_on;		/* --geometry default */
	const char *tool_file;		/* --tool-file */
};

/* The card model's documented plant, for what differs from it. */
static struct sh2000_plant_config plant_default(void)
{
	struct sh2000_sim_config c;

	sh2000_sim_config_default(&c);
	return c.axis[0];
}
#define PLANT_DEFAULT plant_default()

/* --mass (> 0) or --friction (>= 0): every axis' value, at most max. */
static int plant_option(const char *opt, const char *arg, int positive,
			double max, double *v)
{
	if (sh2000_tool_double(arg, v) < 0 || *v < 0 || (positive && *v == 0) ||
	    *v > max)
		return sh2000_tool_usage(NULL, positive ?
					 "%s: '%s' is not a number above 0 and at most %g" :
					 "%s: '%s' is not a number in 0..%g", opt, arg, max);
	return -1;
}

/* "real time", "free-running", with the clock's error if any. */
static void print_mode(const struct serve_opts *o)
{
	printf("%s", (o->flags & SH2000_SIM_SERVER_FREE_RUN) ? "free-running" :
							       "real time");
	if (o->ppm != 0.0)
		printf(", clock %+g ppm", o->ppm);
	if (o->cfg.axis[0].mass_kg != PLANT_DEFAULT.mass_kg ||
	    o->cfg.axis[0].friction_ns_per_m != PLANT_DEFAULT.friction_ns_per_m)
		printf(", plant %g kg, %g N/(m/s)", o->cfg.axis[0].mass_kg,
		       o->cfg.axis[0].friction_ns_per_m);
	if (o->geometry_on)
		printf(", geometry default");
	if (o->gantry_on) {
		printf(", gantry %c+%c", sh2000_tool_axis_name(o->gantry.side_a),
		       sh2000_tool_axis_name(o->gantry.side_b));
		if (o->gantry.carriage_axis >= 0)
			printf(" carriage %c", sh2000_tool_axis_name(
				       (unsigned int)o->gantry.carriage_axis));
	}
}

/* --gantry A+B[:C]: the sides, and the carriage's axis (default the
 * first axis that is not a side; '-' none). -1, or exit 2 worded. */
static int gantry_option(const char *arg, struct serve_opts *o)
{
	struct sh2000_gantry_config *g = &o->gantry;
	char a[2] = { 0, 0 }, b[2] = { 0, 0 }, c[2] = { 0, 0 };
	int ia, ib, ic = -1;
	size_t n = strlen(arg);

	if ((n != 3 && n != 5) || arg[1] != '+' || (n == 5 && arg[3] != ':'))
		return sh2000_tool_usage(NULL,
			"--gantry: '%s' is not A+B or A+B:C (axes, e.g. y+z)", arg);
	a[0] = arg[0];
	b[0] = arg[2];
	ia = sh2000_tool_axis(a);
	ib = sh2000_tool_axis(b);
	if (n == 5 && arg[4] != '-') {
		c[0] = arg[4];
		ic = sh2000_tool_axis(c);
		if (ic < 0 || ic == ia || ic == ib)
			return sh2000_tool_usage(NULL,
				"--gantry %s: the carriage's axis '%s' is not an axis other than the sides",
				arg, c);
	}
	if (ia < 0 || ib < 0 || ia == ib)
		return sh2000_tool_usage(NULL,
			"--gantry %s: the sides are not two different axes (x y z a)", arg);
	for (unsigned int i = 0; n == 3 && ic < 0 && i < SH2000_AXES; i++)
		if ((int)i != ia && (int)i != ib)
			ic = (int)i;	/* the loop ends at the first */
	sh2000_gantry_config_default(g);
	g->side_a = (unsigned int)ia;
	g->side_b = (unsigned int)ib;
	g->carriage_axis = ic;
	o->gantry_on = 1;
	return -1;
}

/*
 * The servo loop (this thread: sh2000_sim_server_run runs in it) takes
 * SCHED_FIFO at o->priority when permitted (root, CAP_SYS_NICE, or an
 * RLIMIT_RTPRIO that allows it); when not, it says so and goes on with
 * ordinary scheduling. A free-running card runs cycles back to back, a
 * busy loop that must not be real-time.
 */
static void take_priority(const struct serve_opts *o)
{
	struct sched_param sp = { .sched_priority = o->priority };

	if (!o->priority || (o->flags & SH2000_SIM_SERVER_FREE_RUN))
		return;
	if (sched_setscheduler(0, SCHED_FIFO | SCHED_RESET_ON_FORK, &sp) == 0)
		return;
	sh2000_tool_msg("no real-time priority (SCHED_FIFO %d: %s): on a busy "
			"machine the card's servo cycles come late; allow it "
			"(sh2000-sim(1), PRIORITY) or use --priority=0",
			o->priority, strerror(errno));
}

/* The machine behind the card, before it runs: its clock, a gantry, and
 * with --geometry default the card model's default errors. All checked
 * when parsed (the default geometry by the model's own tests): cannot
 * fail. */
static void configure(struct sh2000_sim_server *s, const struct serve_opts *o)
{
	struct sh2000_geometry g;

	(void)sh2000_sim_server_set_clock_ppm(s, o->ppm);
	if (o->gantry_on)
		(void)sh2000_sim_server_set_gantry(s, &o->gantry);
	if (!o->geometry_on)
		return;
	sh2000_geometry_default(&g);
	(void)sh2000_sim_server_set_geometry(s, &g);
}

/* --tool-file: the interferometer's reading after the last cycle */
static int write_tool(struct sh2000_sim_server *s, const struct serve_opts *o)
{
	double t[SH2000_AXES];
	FILE *f;

	if (!o->tool_file)
		return 0;
	sh2000_sim_server_tool_position(s, t);
	f = fopen(o->tool_file, "w");
	if (f) {
		fprintf(f, "tool %.6f %.6f %.6f %.6f\n", t[0], t[1], t[2], t[3]);
		if (fclose(f) == 0)
			return 0;
	}
	sh2000_tool_msg("--tool-file %s: %s", o->tool_file, strerror(errno));
	return -1;
}

static int serve_name(const char *name, const struct serve_opts *o)
{
	struct sh2000_sim_server *s;
	char path[256], msg[512];
	struct stat sb;
	int stale, r;

	/* the library replaces a dead owner's object silently: say so */
	snprintf(path, sizeof(path), "/dev/shm/sh2000-%s", name);
	stale = stat(path, &sb) == 0;
	msg[0] = '\0';
	r = sh2000_sim_server_create(&s, name, &o->cfg, o->flags, msg,
				     sizeof(msg));
	if (r < 0) {
		sh2000_tool_msg("%s", msg[0] ? msg : sh2000_strerror(r));
		return SH2000_EXIT_DEVICE;
	}
	/* checked when parsed: cannot fail */
	configure(s, o);
	take_priority(o);
	served = s;
	if (stale)
		sh2000_tool_msg("sim:%s: replaced %s left by a server that is gone",
				name, sh2000_sim_server_shm_name(s));
	if (!o->quiet) {
		printf("sh2000-sim: serving sim:%s at %s (pid %d, ", name,
		       sh2000_sim_server_shm_name(s), (int)getpid());
		print_mode(o);
		printf(")\n");
		fflush(stdout);
	}
	print_ready(o->quiet, o->ready_fd);
	if (!stop_requested)
		r = sh2000_sim_server_run(s);
	if (!o->quiet) {
		printf("sh2000-sim: stopped after %llu servo cycles, %s removed\n",
		       (unsigned long long)sh2000_sim_server_cycles(s),
		       sh2000_sim_server_shm_name(s));
		fflush(stdout);
	}
	served = NULL;
	if (write_tool(s, o) < 0 && r >= 0)
		r = -EIO;
	sh2000_sim_server_destroy(s);
	return r < 0 ? SH2000_EXIT_CARD : SH2000_EXIT_OK;
}

/* The card model on a RAM someone else owns: the kernel simulated card's
 * DSP page (one page, MAP_SHARED only) or a plain file. The library's
 * server runs it, with the same real-time loop as for sim:NAME. */
static int serve_attach(const char *path, const struct serve_opts *o)
{
	long page = sysconf(_SC_PAGESIZE);
	size_t maplen = page > 0 ? (size_t)page : 4096;
	struct sh2000_sim_server *s;
	struct stat sb;
	char msg[512];
	uint16_t *ram;
	int fd, r;

	if (maplen < RAM_BYTES)
		maplen = RAM_BYTES;
	fd = open(path, O_RDWR | O_CLOEXEC);
	if (fd < 0) {
		sh2000_tool_msg("%s: cannot open: %s", path, strerror(errno));
		return SH2000_EXIT_DEVICE;
	}
	if (fstat(fd, &sb) < 0) {
		sh2000_tool_msg("%s: stat: %s", path, strerror(errno));
		close(fd);
		return SH2000_EXIT_DEVICE;
	}
	if (S_ISREG(sb.st_mode) && sb.st_size < RAM_BYTES) {
		sh2000_tool_msg("%s: %lld bytes, the RAM needs %u",
				path, (long long)sb.st_size,
				RAM_BYTES);
		close(fd);
		return SH2000_EXIT_DEVICE;
	}
	if (!S_ISREG(sb.st_mode) && !S_ISCHR(sb.st_mode)) {
		sh2000_tool_msg("%s: not a file or a character device", path);
		close(fd);
		return SH2000_EXIT_DEVICE;
	}
	ram = mmap(NULL, maplen, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
	if (ram == MAP_FAILED) {
		sh2000_tool_msg("%s: mmap of %zu bytes: %s", path, maplen,
				strerror(errno));
		close(fd);
		return SH2000_EXIT_DEVICE;
	}
	close(fd);
	msg[0] = '\0';
	r = sh2000_sim_server_attach(&s, ram, &o->cfg, o->flags, msg, sizeof(msg));
	if (r < 0) {
		sh2000_tool_msg("%s: %s", path, msg[0] ? msg : sh2000_strerror(r));
		munmap(ram, maplen);
		return SH2000_EXIT_CARD;
	}
	configure(s, o);
	take_priority(o);
	served = s;
	if (!o->quiet) {
		printf("sh2000-sim: card model attached to %s (pid %d, ", path,
		       (int)getpid());
		print_mode(o);
		printf(")\n");
		fflush(stdout);
	}
	print_ready(o->quiet, o->ready_fd);
	if (!stop_requested)
		r = sh2000_sim_server_run(s);
	if (!o->quiet) {
		printf("sh2000-sim: stopped after %llu servo cycles, %s detached\n",
		       (unsigned long long)sh2000_sim_server_cycles(s), path);
		fflush(stdout);
	}
	served = NULL;
	if (write_tool(s, o) < 0 && r >= 0)
		r = -EIO;
	sh2000_sim_server_destroy(s);
	munmap(ram, maplen);
	return r < 0 ? SH2000_EXIT_CARD : SH2000_EXIT_OK;
}

/* One option (getopt's c, optarg). Returns -1 to go on, else the exit
 * status main() returns. */
static int option(int c, const char *arg, const char **attach,
		  struct serve_opts *o)
{
	double v;
	long l;
	int r;

	switch (c) {
	case 'a':
		*attach = arg;
		return -1;
	case 'F':
		o->flags |= SH2000_SIM_SERVER_FREE_RUN;
		return -1;
	case 'c':
		if (sh2000_tool_double(arg, &o->ppm) < 0 ||
		    o->ppm < -100000.0 || o->ppm > 100000.0)
			return sh2000_tool_usage(NULL,
				"--clock-ppm: '%s' is not a number in -100000..100000",
				arg);
		return -1;
	case 'r':
		if (sh2000_tool_long(arg, 0, 1 << 20, &l) < 0)
			return sh2000_tool_usage(NULL,
				"--ready-fd: '%s' is not a file descriptor", arg);
		if (fcntl((int)l, F_GETFD) < 0)
			return sh2000_tool_usage(NULL,
				"--ready-fd: %ld is not open", l);
		o->ready_fd = (int)l;
		return -1;
	case 'p':
		if (sh2000_tool_long(arg, 0, 99, &l) < 0)
			return sh2000_tool_usage(NULL,
				"--priority: '%s' is not a number in 0..99", arg);
		o->priority = (int)l;
		return -1;
	case 'q':
		o->quiet = 1;
		return -1;
	case 'm':
		r = plant_option("--mass", arg, 1, 1e4, &v);
		for (unsigned int a = 0; r < 0 && a < SH2000_AXES; a++)
			o->cfg.axis[a].mass_kg = v;
		return r;
	case 'f':
		r = plant_option("--friction", arg, 0, 1e6, &v);
		for (unsigned int a = 0; r < 0 && a < SH2000_AXES; a++)
			o->cfg.axis[a].friction_ns_per_m = v;
		return r;
	case 'g':
		return gantry_option(arg, o);
	case 'G':
		if (strcmp(arg, "none") && strcmp(arg, "default"))
			return sh2000_tool_usage(NULL,
				"--geometry: '%s' is not none or default", arg);
		o->geometry_on = !strcmp(arg, "default");
		return -1;
	case 'T':
		o->tool_file = arg;
		return -1;
	case 'h':
		usage(stdout);
		return SH2000_EXIT_OK;
	case 'V':
		sh2000_tool_print_version(SH2000_TOOLS_VERSION);
		return SH2000_EXIT_OK;
	default:
		return -2;	/* getopt's '?': main() words it */
	}
}

static int operands(int argc, char **argv, const char *attach)
{
	if (attach && optind != argc)
		return sh2000_tool_usage(NULL,
			"--attach takes no NAME (got '%s')", argv[optind]);
	if (!attach && optind == argc)
		return sh2000_tool_usage(NULL, "missing NAME (or --attach PATH)");
	if (!attach && argc - optind > 1)
		return sh2000_tool_usage(NULL, "one NAME only (got '%s' too)",
					 argv[optind + 1]);
	if (!attach) {
		const char *n = argv[optind];

		if (!*n || strlen(n) > 64 || strchr(n, '/'))
			return sh2000_tool_usage(NULL,
				"bad NAME '%s': 1..64 characters, no '/'", n);
	}
	return -1;
}

int main(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "attach", required_argument, NULL, 'a' },
		{ "free-run", no_argument, NULL, 'F' },
		{ "clock-ppm", required_argument, NULL, 'c' },
		{ "ready-fd", required_argument, NULL, 'r' },
		{ "priority", required_argument, NULL, 'p' },
		{ "quiet", no_argument, NULL, 'q' },
		{ "mass", required_argument, NULL, 'm' },
		{ "friction", required_argument, NULL, 'f' },
		{ "gantry", required_argument, NULL, 'g' },
		{ "geometry", required_argument, NULL, 'G' },
		{ "tool-file", required_argument, NULL, 'T' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ NULL, 0, NULL, 0 },
	};
	struct serve_opts o = { .flags = 0, .ppm = 0.0, .quiet = 0,
				.ready_fd = -1, .priority = SIM_PRIORITY };
	const char *attach = NULL;
	int c, r;

	sh2000_sim_config_default(&o.cfg);
	sh2000_tool_init("sh2000-sim");
	opterr = 0;
	while ((c = getopt_long(argc, argv, "+a:Fc:r:p:qg:hV", opts, NULL)) != -1) {
		r = option(c, optarg, &attach, &o);
		if (r == -2 && optopt && optopt != '?')
			return sh2000_tool_usage(NULL,
				"option -%c: unknown or missing its argument",
				optopt);
		if (r == -2)
			return sh2000_tool_usage(NULL, "unknown option '%s'",
						 argv[optind - 1]);
		if (r >= 0)
			return r;
	}
	r = operands(argc, argv, attach);
	if (r >= 0)
		return r;
	r = install_signals();
	if (r < 0) {
		sh2000_tool_msg("sigaction: %s", strerror(-r));
		return SH2000_EXIT_CARD;
	}
	if (attach)
		return serve_attach(attach, &o);
	return serve_name(argv[optind], &o);
}
