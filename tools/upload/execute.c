// SPDX-License-Identifier: MIT
/*
 * sh2000-upload on the card: enabling the axes the program moves, the
 * run's callbacks (trace samples, progress, the operator's signals), the
 * pauses at M0/M1 and what a failed run says.
 */
#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "upload.h"

volatile sig_atomic_t upl_resume_flag, upl_hold_flag;

static void on_resume(int sig)
{
	(void)sig;
	upl_resume_flag = 1;
	upl_hold_flag = 0;
}

static void on_hold(int sig)
{
	(void)sig;
	upl_hold_flag = 1;
}

void upl_signals(void)
{
	struct sigaction sa;

	sh2000_tool_catch_stop(SH2000_SECOND_COUNTS);
	memset(&sa, 0, sizeof(sa));
	sigemptyset(&sa.sa_mask);
	sa.sa_handler = on_resume;
	sigaction(SIGUSR1, &sa, NULL);
	sa.sa_handler = on_hold;
	sigaction(SIGUSR2, &sa, NULL);
}

void upl_on_sample(void *ctx, const struct sh2000_run_sample *s)
{
	struct upl_runctx *rc = ctx;

	if (rc->trace)
		upl_trace_sample(rc->trace, s);
}

void upl_on_progress(void *ctx, const struct sh2000_run_progress *p)
{
	struct upl_runctx *rc = ctx;

	if (sh2000_tool_stop_asked() && !rc->stop_sent && rc->run) {
		rc->stop_sent = 1;
		upl_report_end(&rc->rep);
		sh2000_tool_msg("stopping on the path (signal; a second one is an emergency stop)");
		sh2000_run_stop(rc->run);
	}
	if (sh2000_tool_stop_asked() >= 2 && !rc->estop_sent && rc->h) {
		rc->estop_sent = 1;
		upl_report_end(&rc->rep);
		sh2000_tool_msg("emergency stop (second signal)");
		sh2000_estop(rc->h, 100);
	}
	/* feed hold (SIGUSR2) and its end (SIGUSR1), on the card's time
	 * base when it has one */
	if (upl_hold_flag && rc->run && !rc->holding) {
		rc->holding = 1;
		upl_report_end(&rc->rep);
		sh2000_tool_msg("feed hold (SIGUSR2); SIGUSR1 resumes");
		sh2000_run_pause(rc->run);
	} else if (!upl_hold_flag && rc->holding) {
		rc->holding = 0;
		upl_resume_flag = 0;
		sh2000_tool_msg("resuming from the feed hold");
		sh2000_run_resume(rc->run);
	}
	if (p->seq >= 0)
		rc->seq = p->seq;
	upl_report_progress(&rc->rep, p);
}

/* Wait for a line on standard input (or its end, or a signal). 1 to
 * resume, 0 to keep waiting. */
static int operator_input(int *stdin_eof)
{
	struct pollfd pf = { .fd = STDIN_FILENO, .events = POLLIN };
	char ch;
	ssize_t k;

	if (poll(&pf, *stdin_eof ? 0 : 1, 200) <= 0)
		return 0;
	while ((k = read(STDIN_FILENO, &ch, 1)) == 1 && ch != '\n')
		;
	if (k == 1)
		return 1;
	if (k == 0 || (k < 0 && errno != EINTR && errno != EAGAIN))
		*stdin_eof = 1;
	return 0;
}

/* What the operator is asked at a tool change (a terminal is there:
 * --pause-on-tool-change needs one). */
static void tool_change_prompt(const struct upl_runctx *rc, const char *where,
			       const struct sh2000_prog_block *b)
{
	const struct sh2000_tool *t = rc->tools ?
		sh2000_tool_table_find(rc->tools, b->tool) : NULL;

	if (b->tool == 0) {
		sh2000_tool_msg("%s: tool change: take the tool out of the spindle (T0); press Enter when done (Ctrl-C stops)",
				where);
		return;
	}
	if (t)
		sh2000_tool_msg("%s: tool change: put tool %d in the spindle (pocket %d, Z offset %.4f mm, diameter %.4f mm%s%s); press Enter when it is in (Ctrl-C stops)",
				where, b->tool, t->pocket, t->offset[2],
				t->diameter, t->comment ? ": " : "",
				t->comment ? t->comment : "");
	else
		sh2000_tool_msg("%s: tool change: put tool %d in the spindle; press Enter when it is in (Ctrl-C stops)",
				where, b->tool);
}

int upl_pause(void *ctx, const struct sh2000_prog_block *b)
{
	struct upl_runctx *rc = ctx;
	char where[300];

	upl_report_end(&rc->rep);
	sh2000_prog_block_where(b, where, sizeof(where));
	if (b->tool_change)
		tool_change_prompt(rc, where, b);
	else if (isatty(STDIN_FILENO))
		sh2000_tool_msg("%s: %s: paused; press Enter to resume (Ctrl-C stops)",
				where, b->u.optional ? "M1" : "M0");
	else
		sh2000_tool_msg("%s: %s: paused; resuming on a line on standard input or SIGUSR1 (pid %ld)",
				where, b->u.optional ? "M1" : "M0",
				(long)getpid());
	upl_resume_flag = 0;
	while (!upl_resume_flag && !operator_input(&rc->stdin_eof)) {
		struct sh2000_status st;
		int e;

		if (sh2000_tool_stop_asked())
			return -ECANCELED;
		if (sh2000_backend(rc->h) == SH2000_BACKEND_SIM)
			continue;
		/* keep the card's host timeout fed, and hear of faults */
		e = sh2000_poll(rc->h, &st);
		if (e >= 0)
			e = sh2000_status_error(rc->h, &st);
		if (e < 0) {
			rc->pause_error = e;
			return e;
		}
	}
	sh2000_tool_msg("resuming");
	return 0;
}

int upl_run_fail(const struct upl_runctx *rc, const char *file, int e)
{
	char where[300] = "";

	if (rc->seq > 0)
		snprintf(where, sizeof(where), "%s:%lld", file,
			 (long long)rc->seq);
	if (e == -ECANCELED) {
		sh2000_tool_msg("%s%sstopped by the operator; the card is at rest on the path",
				where, where[0] ? ": " : "");
		return SH2000_EXIT_STOPPED;
	}
	if (rc->pause_error)
		return sh2000_tool_fail(rc->h, e, "while paused");
	sh2000_tool_msg("%s", sh2000_run_error(rc->run));
	if (where[0])
		sh2000_tool_msg("%s: the card was running this block", where);
	if (e == -SH2000_ESTOPPED)
		return SH2000_EXIT_STOPPED;	/* an operator's STOP elsewhere */
	return sh2000_tool_exit_code(e);
}

void upl_axes_text(unsigned int mask, char *buf)
{
	char *p = buf;

	for (unsigned int a = 0; a < SH2000_AXES; a++)
		if (mask & (1u << a)) {
			if (p != buf)
				*p++ = ' ';
			*p++ = sh2000_tool_axis_name(a);
		}
	*p = 0;
}

int upl_enable_axes(struct sh2000 *h, const struct upl_opts *o,
		    unsigned int need)
{
	struct sh2000_status st;
	unsigned int off = 0, a;
	char names[16];
	int e;

	e = sh2000_poll(h, &st);
	if (e < 0)
		return sh2000_tool_fail(h, e, "status");
	for (a = 0; a < SH2000_AXES; a++)
		if ((need & (1u << a)) &&
		    !(st.axis[a].state & SH2000_AXIS_ENABLED))
			off |= 1u << a;
	if (!off)
		return SH2000_EXIT_OK;
	upl_axes_text(off, names);
	if (o->no_enable) {
		sh2000_tool_msg("%s: axes %s not enabled (--no-enable; enable them with sh2000ctl enable); nothing moved",
				sh2000_device(h), names);
		return SH2000_EXIT_CARD;
	}
	if (!o->quiet)
		sh2000_tool_msg("%s: enabling axes %s", sh2000_device(h), names);
	e = sh2000_enable(h, off);
	if (e < 0)
		return sh2000_tool_fail(h, e, "enable");
	return SH2000_EXIT_OK;
}
