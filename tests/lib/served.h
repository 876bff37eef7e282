/* SPDX-License-Identifier: MIT */
/*
 * Helpers of the real-time fault matrices (docs/faults.md) on a served card
 * (sim:NAME): the card served by a child process that injects faults on
 * request, the host activities of the matrix (idle, a run, one record per
 * period) with a hook at the fault's moment. lib_matrix_shm, lib_matrix_cross and lib_matrix_tools use them.
 */
#ifndef SH2000_TEST_SERVED_H
#define SH2000_TEST_SERVED_H

#include <sys/types.h>

#include "rt.h"
#include "simtest.h"

#define SERVED_FEED	100.0	/* mm/s along X */
#define SERVED_AT_POINT	150u	/* records streamed before the fault */
/*
 * What comes on top of a documented time in real time: the kernel's
 * wake-up of the SCHED_FIFO card, hosts and watchers (rt.h; an ordinary,
 * not PREEMPT_RT kernel) and the runner's own step between two looks at
 * the card (up to 10 ms in a run). At most 7 ms measured, also under ASan
 * with a busy process per core beside and a load average of 13.
 */
#define SERVED_SLACK_MS	15.0

/* CLOCK_MONOTONIC in ms. */
double served_now_ms(void);
/* "sim:mx-WHAT-PID" into buf. */
void served_name(char *buf, size_t len, const char *what);
/* Until the served card's own clock has run ms further: the card's time,
 * not the host's, so a descheduled test waits no less. Probed, which is
 * no host heartbeat. Fails after 20 times that of host time. */
void served_card_wait(struct sh2000_sim_server *s, double ms);
/* Open dev or fail the test. */
struct sh2000 *served_open(const char *dev);

/* ---- a card served by a child process -------------------------------- */

struct served_card {
	pid_t pid;
	int cmd, ack;	/* requests to the child, its answers */
};

/* Start a server of dev (sim:NAME) in a child; returns when it serves. */
void served_spawn(struct served_card *c, const char *dev);
/* sh2000_sim_server_inject() in the child; returns once it is applied. */
void served_inject(struct served_card *c, enum sh2000_inject what,
		   unsigned int axis, unsigned int arg);
/* Stop the server cleanly (the object unlinked) and reap it. */
void served_end(struct served_card *c);
/* SIGKILL it (the object stays behind) and reap it. */
void served_kill(struct served_card *c);

/* The injection's argument as the matrices use it: a RAM flip hits the
 * record pushed last (the ring's HEAD read through h), a limit switch
 * is the + one. */
unsigned int served_fault_arg(struct sh2000 *h, enum sh2000_inject what);

/* ---- the host's activities --------------------------------------------- */

enum served_activity { ACT_IDLE, ACT_RUN, ACT_PERIOD, ACTS };

extern const char *const served_act_name[ACTS];

struct served_act {
	int signal_fd;		/* written once at the fault (-1: none) */
	pid_t victim;		/* or killed there (0: none) */
	void (*at)(void *arg);	/* or this called there (NULL: none) */
	void *arg;
	double t_fault;		/* served_now_ms() then */
	int done;		/* the fault's moment came */
};

/* Enable all axes and run activity a until it fails (idle: until a poll
 * fails; pause() without a victim); the fault's moment is after
 * SERVED_AT_POINT records (idle: at once). Returns the error. */
int served_activity(struct sh2000 *h, enum served_activity a,
		    struct served_act *c);

#endif
