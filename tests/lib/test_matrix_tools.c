/* SPDX-License-Identifier: MIT */
/*
 * The fault matrix with the tools as processes (docs/faults.md): the built
 * `sh2000ctl move` and `sh2000-upload` (paths in $SH2000_CTL and
 * $SH2000_UPLOAD) stream a 200 mm line along X at 100 mm/s to a card this
 * test serves in a thread (sim:NAME, real time). After 150 records (the
 * ring's HEAD) the test injects each card fault, or kills the tool with
 * SIGKILL, and watches the card through the server's probe (no poll: the
 * tool stays the card's only host). Each cell checks that the set-point
 * stops within the documented time, that the tool exits with the
 * documented status (docs/tools.md) within the documented time and that
 * its message names the fault, that the right fault is latched and named,
 * that `sh2000ctl reset` brings the card back and that the next run of the
 * tool works; it prints the table docs/faults.md carries.
 */
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "served.h"

extern char **environ;

#define HB_MS	(SH2000_HEARTBEAT_LIMIT_SHM_NS * 1e-6)
#define STILL_MS	100.0	/* the card at rest this long: the cell ends */
#define CELL_MS		3000.0	/* longest a cell may take after the fault */
/*
 * A tool is a process of its own: what waits on it (its exit; the card's
 * stop when the tool must stop it, after a stopped heartbeat) also waits
 * for its way out (the emergency stop's acknowledgement, the message, the
 * end of a process). The tools inherit this test's SCHED_FIFO (main), as
 * a host with a deadline runs, so a busy machine does not delay them: a
 * few ms (at most 2 ms over the bounds measured, also under ASan at a load
 * average of 13). Those bounds allow this much on top of SERVED_SLACK_MS,
 * and three times the worst lateness of the watcher's own wake-ups during
 * the cell (without the privilege for SCHED_FIFO: the machine's load).
 */
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
/* the tools built with the sanitizers run 2..3 times slower */
#define TOOL_SLACK_MS	60.0
#else
#define TOOL_SLACK_MS	30.0
#endif

enum tool { T_MOVE, T_UPLOAD, TOOLS };

static const char *const tool_name[TOOLS] = { "sh2000ctl move",
					      "sh2000-upload" };

#define KILL_TOOL	SH2000_INJECT_CLEAR	/* the row that kills the tool */

struct fault {
	const char *name;
	enum sh2000_inject what;
	int exit_code;		/* the tool's status (-N: killed by signal N) */
	const char *says;	/* in the tool's message */
	int latched;		/* what the card's status names afterwards */
	int tool_stops;		/* the card stops when the tool stops it */
	/* documented bounds (docs/faults.md), ms after the injection: the
	 * set-point at rest, the tool's exit */
	double stop_ms, exit_ms;
};

/*
 * The bounds of lib_matrix with the heartbeat limit of sim:NAME (100 ms,
 * not 10: a served model is an ordinary process) and, for every row,
 * SERVED_SLACK_MS of scheduling; a killed tool leaves the card to its host
 * timeout (100 ms) and a controlled stop (21 ms at 100 mm/s).
 */
static const struct fault faults[] = {
	{ "heartbeat stop", SH2000_INJECT_HEARTBEAT_STOP, 1, "heartbeat",
	  -SH2000_EESTOP, 1, HB_MS + 6.0, HB_MS + 6.0 },
	{ "DSP stall", SH2000_INJECT_DSP_STALL, 1, "heartbeat",
	  -SH2000_EESTOP, 0, 0.0, HB_MS + 16.0 },
	{ "RAM word flip", SH2000_INJECT_RAM_FLIP, 4, "rejected",
	  -SH2000_EREJECTED, 0, 150.0, 156.0 },
	{ "axis jam", SH2000_INJECT_JAM, 4, "following error",
	  -SH2000_EFERR, 0, 30.0, 36.0 },
	{ "limit switch", SH2000_INJECT_LIMIT, 4, "limit switch",
	  -SH2000_EHARD_LIMIT, 0, 23.0, 8.0 },
	{ "segment drop", SH2000_INJECT_DROP_SEGMENT, 4, "rejected",
	  -SH2000_EREJECTED, 0, 150.0, 156.0 },
	{ "counter glitch", SH2000_INJECT_COUNTER_GLITCH, 4, "counter",
	  -SH2000_ECOUNTER, 0, 23.0, 8.0 },
	{ "tool SIGKILL", KILL_TOOL, -SIGKILL, NULL,
	  -SH2000_EHOST_TIMEOUT, 0, 100.0 + 21.0, 0.0 },
};

#define NFAULTS (sizeof(faults) / sizeof(faults[0]))

struct cell {
	int ran;
	int status;		/* exit code, or -signal */
	char said[200];		/* the line of its message naming the fault */
	char block[100];	/* and the one naming the block (upload) */
	double exit_ms, stop_ms;
	unsigned int state, card_faults;
	int named;		/* the card's status error afterwards */
	double coast_mm_s;	/* X's carriage then, at the reset */
	double late_ms;
};

static struct cell cells[NFAULTS][TOOLS];
static char workdir[] = "/tmp/sh2000-mxtools-XXXXXX";

/* ---- running a tool ----------------------------------------------------- */

static const char *tool_path(const char *env)
{
	const char *p = getenv(env);

	if (!p || !*p)
		fail_msg("$%s is not set: run this test through ctest", env);
	return p;
}

/* Start argv with stdout and stderr into files of the work folder. */
static pid_t spawn_tool(char *const argv[], const char *err_file)
{
	posix_spawn_file_actions_t fa;
	char out[300];
	pid_t pid;

	snprintf(out, sizeof(out), "%s/out", workdir);
	posix_spawn_file_actions_init(&fa);
	posix_spawn_file_actions_addopen(&fa, 1, out, O_WRONLY | O_CREAT |
					 O_TRUNC, 0644);
	posix_spawn_file_actions_addopen(&fa, 2, err_file, O_WRONLY | O_CREAT |
					 O_TRUNC, 0644);
	if (posix_spawn(&pid, argv[0], &fa, NULL, argv, environ))
		fail_msg("cannot start %s", argv[0]);
	posix_spawn_file_actions_destroy(&fa);
	return pid;
}

static int status_of(int st)
{
	return WIFEXITED(st) ? WEXITSTATUS(st) :
	       WIFSIGNALED(st) ? -WTERMSIG(st) : -1000;
}

/* Print a file to stderr (what a failed tool said). */
static void show(const char *file)
{
	char line[512];
	FILE *f = fopen(file, "r");

	while (f && fgets(line, sizeof(line), f))
		fprintf(stderr, "  %s", line);
	if (f)
		fclose(f);
}

/* Run argv to its end: its status; a status other than want fails. */
static void run_tool(char *const argv[], int want)
{
	char err[300];
	int st;

	snprintf(err, sizeof(err), "%s/err-run", workdir);
	waitpid(spawn_tool(argv, err), &st, 0);
	if (status_of(st) != want) {
		show(err);
		fail_msg("%s %s %s: status %d, expected %d", argv[0], argv[3],
			 argv[4] ? argv[4] : "", status_of(st), want);
	}
}

/* The motion of a cell (X to 200 mm at 100 mm/s), or the next run (Y to
 * 5 mm at 50 mm/s), as tool t: argv in a, with its strings in buf. */
static void tool_argv(enum tool t, const char *dev, int next, char *a[12],
		      char buf[300])
{
	int n = 0;

	if (t == T_MOVE) {
		a[n++] = (char *)tool_path("SH2000_CTL");
		a[n++] = "-d";
		a[n++] = (char *)dev;
		a[n++] = "enable";
		a[n++] = next ? "y" : "x";
		a[n++] = "+";
		a[n++] = "move";
		a[n++] = next ? "y=5" : "x=200";
		a[n++] = "--feed";
		a[n++] = next ? "50" : "100";
	} else {
		snprintf(buf, 300, "%s/%s.ngc", workdir, next ? "next" : "line");
		a[n++] = (char *)tool_path("SH2000_UPLOAD");
		a[n++] = "-q";
		a[n++] = "-d";
		a[n++] = (char *)dev;
		a[n++] = buf;
	}
	a[n] = NULL;
}

static void write_file(const char *name, const char *text)
{
	char path[300];
	FILE *f;

	snprintf(path, sizeof(path), "%s/%s", workdir, name);
	f = fopen(path, "w");
	if (!f || fputs(text, f) < 0 || fclose(f))
		fail_msg("cannot write %s", path);
}

/* ---- one cell ----------------------------------------------------------- */

struct watch {
	struct sh2000_sim_server *s;
	struct sh2000 *h;	/* reads HEAD and, at the end, the status */
	const struct fault *f;
	pid_t tool;
	int exited, status;
	double t_inj, t_moved, t_exit;
	double late_ms;		/* the watcher's worst wake-up, late by */
	double cmd[SH2000_AXES];
};

/*
 * 1 when an enabled axis' set-point moved since the last look. A disabled
 * axis' set-point follows its encoder (the card does not drive it; a
 * carriage let go of coasts for a second): that is the machine, not the
 * card. The axes' state words are read from the RAM, not polled: a poll
 * would feed the card's host timeout.
 */
static int moved(struct watch *w)
{
	struct sh2000 *h = w->h;
	struct sh2000_probe p;
	uint16_t ax[SH2000_AXES];
	int m = 0;

	sh2000_sim_server_probe(w->s, &p);
	CHECK(sh2000_ram_read(h, SH2000_W_AXIS_STATE(0), SH2000_AXES, ax));
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		if (p.axis[a].fine_cmd != w->cmd[a] &&
		    (ax[a] & SH2000_AXIS_ENABLED)) {
			m = 1;
			if (served_now_ms() - w->t_inj > CELL_MS - 1.0)
				fprintf(stderr, "state %u: axis %u moved %.1f counts, v %.0f counts/s, dac %d, state 0x%04x\n",
					p.state, a, p.axis[a].fine_cmd - w->cmd[a],
					p.axis[a].velocity, p.axis[a].dac, ax[a]);
		}
		w->cmd[a] = p.axis[a].fine_cmd;
	}
	return m;
}

static void reap(struct watch *w)
{
	int st;

	if (!w->exited && waitpid(w->tool, &st, WNOHANG) == w->tool) {
		w->exited = 1;
		w->status = status_of(st);
		w->t_exit = served_now_ms();
	}
}

/* Wait for record AT_POINT of the tool's motion, then the fault (or the
 * kill). 0 when the tool ended first: a precondition, not the outcome. */
static int inject_at_point(struct watch *w)
{
	const struct timespec tick = { 0, 200000 };
	struct sh2000 *h = w->h;
	uint16_t head0, head;
	double t0 = served_now_ms();

	CHECK(sh2000_ram_read(h, SH2000_W_HEAD, 1, &head0));
	for (;;) {
		reap(w);
		if (w->exited)
			return 0;
		CHECK(sh2000_ram_read(h, SH2000_W_HEAD, 1, &head));
		if ((uint16_t)(head - head0) >= SERVED_AT_POINT)
			break;
		/* 150 records are 300 ms of motion */
		if (served_now_ms() - t0 > CELL_MS) {
			kill(w->tool, SIGKILL);
			fail_msg("%s: the tool pushed %u of the %u records before the fault in %.0f ms",
				 w->f->name, (uint16_t)(head - head0),
				 SERVED_AT_POINT, CELL_MS);
		}
		nanosleep(&tick, NULL);
	}
	if (w->f->what == KILL_TOOL) {
		kill(w->tool, SIGKILL);
	} else if (sh2000_sim_server_inject(w->s, w->f->what, 0,
					    served_fault_arg(w->h, w->f->what)) < 0) {
		fail_msg("inject %s failed", w->f->name);
	}
	w->t_inj = served_now_ms();
	w->t_moved = w->t_inj;
	moved(w);		/* the set-point at the injection */
	return 1;
}

/* Until the tool has exited and the set-point stood still STILL_MS. */
static void watch_after(struct watch *w)
{
	const struct timespec tick = { 0, 200000 };
	double t, last = w->t_inj;

	for (;;) {
		t = served_now_ms();
		if (t - last - 0.2 > w->late_ms)
			w->late_ms = t - last - 0.2;
		last = t;
		if (moved(w))
			w->t_moved = t;
		reap(w);
		if (w->exited && t - w->t_moved >= STILL_MS &&
		    t - w->t_exit >= STILL_MS)
			return;
		if (t - w->t_inj > CELL_MS) {
			if (!w->exited)
				kill(w->tool, SIGKILL);
			fail_msg("%s: %s after %.0f ms (tool status %d)", w->f->name,
				 w->exited ? "the card still moves" :
				 "the tool has not exited", CELL_MS, w->status);
		}
		nanosleep(&tick, NULL);
	}
}

/* The line of the tool's message that names the fault, without the
 * tool's name and the device, into said ("" when none does). */
static void find_said(const char *file, const char *dev, const char *says,
		      char *said, size_t len)
{
	char line[512], *p;
	FILE *f = fopen(file, "r");

	said[0] = '\0';
	while (f && says && fgets(line, sizeof(line), f)) {
		if (!strstr(line, says))
			continue;
		line[strcspn(line, "\n")] = '\0';
		p = strchr(line, ':');
		p = p ? p + 2 : line;
		if (!strncmp(p, dev, strlen(dev)) && p[strlen(dev)] == ':')
			p += strlen(dev) + 2;
		/* cut to fit: the table wants the start */
		if (strlen(p) >= len)
			p[len - 1] = '\0';
		strcpy(said, p);
		break;
	}
	if (f)
		fclose(f);
}

/*
 * The card after the cell, the fault cleared: state, faults, the error
 * its status names, and how fast X's carriage still goes. A carriage the
 * card let go of (X disabled by the fault at 100 mm/s) coasts on its
 * friction: the reset and the next run come at once, while it does.
 */
static void card_after(struct watch *w, struct cell *c)
{
	struct sh2000 *h = w->h;
	struct sh2000_status st;
	struct sh2000_probe p;

	CHECK(sh2000_sim_server_inject(w->s, SH2000_INJECT_CLEAR, 0, 0));
	CHECK(sh2000_sleep_ns(h, 20000000ull));
	sh2000_sim_server_probe(w->s, &p);
	c->coast_mm_s = fabs(p.axis[0].velocity) * 1e-5;
	CHECK(sh2000_poll(h, &st));
	c->state = st.card_state;
	c->card_faults = st.card_faults;
	c->named = sh2000_status_error(h, &st);
}

/* sh2000ctl reset, then the tool's next run: Y to 5 mm, exit 0, the
 * card idle there. */
static void recover(enum tool t, const char *dev, struct sh2000 *h)
{
	char *reset[] = { (char *)tool_path("SH2000_CTL"), "-d", (char *)dev,
			  "reset", NULL };
	char *argv[12], buf[300];
	struct sh2000_status st;

	run_tool(reset, 0);
	tool_argv(t, dev, 1, argv, buf);
	run_tool(argv, 0);
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_state, SH2000_STATE_IDLE);
	assert_int_equal(st.card_faults, 0);
	assert_true(fabs(st.axis[1].cmd_mm - 5.0) < 1e-3);
}

/* One cell: 1, or 0 when the tool ended before the fault. */
static int tool_cell_once(unsigned int fi, enum tool t)
{
	const struct fault *f = &faults[fi];
	struct cell *c = &cells[fi][t];
	struct watch w = { .f = f };
	char dev[80], msg[256], err[300], *argv[12], buf[300];
	int ok;

	served_name(dev, sizeof(dev), "tool");
	snprintf(err, sizeof(err), "%s/err", workdir);
	if (sh2000_sim_server_create(&w.s, dev + 4, NULL, 0, msg, sizeof(msg)))
		fail_msg("server: %s", msg);
	if (rt_server_start(w.s))
		fail_msg("server %s does not start", dev);
	w.h = served_open(dev);
	tool_argv(t, dev, 0, argv, buf);
	w.tool = spawn_tool(argv, err);
	ok = inject_at_point(&w);
	if (ok) {
		watch_after(&w);
		c->ran = 1;
		c->status = w.status;
		c->exit_ms = w.t_exit - w.t_inj;
		c->stop_ms = w.t_moved - w.t_inj;
		c->late_ms = w.late_ms;
		find_said(err, dev, f->says, c->said, sizeof(c->said));
		card_after(&w, c);
		/* sh2000-upload names the block the card was running too */
		find_said(err, dev, t == T_UPLOAD && f->says ?
			  "line.ngc:2: the card was running this block" : NULL,
			  c->block, sizeof(c->block));
		if (c->status != f->exit_code || (f->says && !c->said[0]) ||
		    (t == T_UPLOAD && f->says && !c->block[0])) {
			show(err);
			fail_msg("%s / %s: status %d, expected %d and '%s'%s",
				 f->name, tool_name[t], c->status, f->exit_code,
				 f->says ? f->says : "",
				 t == T_UPLOAD ? " and the block" : "");
		}
		recover(t, dev, w.h);
	} else {
		fprintf(stderr, "%s / %s: the tool ended before the fault:\n",
			f->name, tool_name[t]);
		show(err);
	}
	sh2000_close(w.h);
	sh2000_sim_server_destroy(w.s);
	return ok;
}

static void tool_cell(unsigned int fi, enum tool t)
{
	const struct fault *f = &faults[fi];
	const struct cell *c = &cells[fi][t];
	double slack, tool;
	int tries = 0;

	while (!tool_cell_once(fi, t))
		if (++tries == 3)
			fail_msg("%s / %s: the tool ended before the fault %d times",
				 f->name, tool_name[t], tries);
	if (c->named != f->latched)
		fail_msg("%s / %s: the card names %d (%s), expected %d", f->name,
			 tool_name[t], c->named, sh2000_strerror(c->named),
			 f->latched);
	/* a stalled DSP lets X go at its speed when it runs again (at the
	 * clear, 20 ms before the reset): the next run, which worked, must
	 * have started while X coasted, 80 mm/s on an idle
	 * machine, 1 mm/s 0.4 s later */
	if (f->what == SH2000_INJECT_DSP_STALL && c->coast_mm_s < 1.0)
		fail_msg("%s / %s: X at %.2f mm/s at the reset: the next run did not meet a coasting carriage",
			 f->name, tool_name[t], c->coast_mm_s);
	/* the tool's few wake-ups on its way out are each as late as the
	 * watcher's worst at most: the machine's load during the cell */
	tool = TOOL_SLACK_MS + 3.0 * c->late_ms;
	/* a watcher that woke up late saw the last move late */
	slack = SERVED_SLACK_MS + c->late_ms + (f->tool_stops ? tool : 0.0);
	if (c->stop_ms > f->stop_ms + slack)
		fail_msg("%s / %s: set-point moved %.1f ms after the fault (bound %.1f + %.0f; the watcher woke up to %.1f ms late)",
			 f->name, tool_name[t], c->stop_ms, f->stop_ms, slack,
			 c->late_ms);
	slack = SERVED_SLACK_MS + tool;
	if (f->what != KILL_TOOL && c->exit_ms > f->exit_ms + slack)
		fail_msg("%s / %s: the tool exited %.1f ms after the fault (bound %.1f + %.0f; the watcher woke up to %.1f ms late)",
			 f->name, tool_name[t], c->exit_ms, f->exit_ms, slack,
			 c->late_ms);
}

static void test_tools(void **state)
{
	(void)state;
	for (unsigned int fi = 0; fi < NFAULTS; fi++)
		for (unsigned int t = 0; t < TOOLS; t++)
			tool_cell(fi, t);
}

static void print_table(void)
{
	printf("| fault | tool | the tool said | exit status | in ms | set-point still after ms | card after (state, faults) | X coasting at the reset, mm/s |\n");
	printf("| --- | --- | --- | ---: | ---: | ---: | --- | ---: |\n");
	for (unsigned int fi = 0; fi < NFAULTS; fi++)
		for (unsigned int t = 0; t < TOOLS; t++) {
			const struct cell *c = &cells[fi][t];
			char st[32], ms[32] = "-";

			if (!c->ran)
				continue;
			if (c->status < 0)
				snprintf(st, sizeof(st), "SIGKILL");
			else
				snprintf(st, sizeof(st), "%d", c->status);
			/* a killed tool's exit is the kill's */
			if (faults[fi].what != KILL_TOOL)
				snprintf(ms, sizeof(ms), "%.1f", c->exit_ms);
			printf("| %s | %s | %s | %s | %s | %.1f | %u, 0x%04x | %.1f |\n",
			       faults[fi].name, tool_name[t],
			       c->said[0] ? c->said : "-", st, ms,
			       c->stop_ms, c->state, c->card_faults,
			       c->coast_mm_s);
		}
}

static int setup(void **state)
{
	const char *asan = getenv("ASAN_OPTIONS");
	char opts[512];

	(void)state;
	/*
	 * In a sanitizer build LeakSanitizer scans a tool's memory as it
	 * exits: 0.5 s at a load average of 14, not the tool's way out. The
	 * tools' own tests (tests/tools) check their leaks; here the exit is
	 * timed. The test itself read its options when it started.
	 */
	snprintf(opts, sizeof(opts), "%s%sdetect_leaks=0", asan ? asan : "",
		 asan && *asan ? ":" : "");
	setenv("ASAN_OPTIONS", opts, 1);
	if (!mkdtemp(workdir))
		return -1;
	write_file("line.ngc", "G21 G90 G17 F6000\nG1 X200\nM2\n");
	write_file("next.ngc", "G21 G90 G17 F3000\nG1 Y5\nM2\n");
	return 0;
}

static int teardown(void **state)
{
	char cmd[400];

	(void)state;
	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", workdir);
	return system(cmd) ? -1 : 0;
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_tools),
	};
	int r;

	/* the hosts whose times the matrix judges, real-time ones (the
	 * processes and tools it starts inherit it), below the card */
	rt_fifo(RT_HOST, 0);
	r = cmocka_run_group_tests(tests, setup, teardown);

	print_table();
	return r;
}
