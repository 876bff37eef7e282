/* SPDX-License-Identifier: MIT */
/*
 * Serving a card model for `sim:NAME`: the shared-memory object
 * /sh2000-NAME (sh2000_shm.h) plays the dual-port RAM, and the firmware
 * runs one servo cycle per servo period in real time (or back to back
 * with SH2000_SIM_SERVER_FREE_RUN); or the same on a RAM the caller
 * mapped (sh2000_sim_server_attach). A cycle lasts the card's servo period
 * as its oscillator makes it (sh2000_sim_server_set_clock_ppm) in
 * CLOCK_MONOTONIC time. Injections and probes take the server's mutex, so
 * they land between two cycles.
 */
#include <errno.h>
#include <pthread.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "card_internal.h"
#include "sh2000/sim.h"
#include "sh2000/sh2000_protocol.h"
#include "sh2000_fpga.h"
#include "sh2000_shm.h"
#include "simutil.h"

struct sh2000_sim_server {
	char shm_name[SH2000_SHM_NAME_MAX + 16];
	struct sh2000_shm *shm;	/* NULL when attached to a caller's RAM */
	int lock_fd;		/* the object, locked while we serve it */
	uint16_t *ram;		/* the dual-port RAM the firmware runs on */
	struct sh2000_fw *fw;
	unsigned int flags;
	pthread_mutex_t lock;	/* the firmware between cycles */
	pthread_t thread;
	int started;
	int stop;		/* atomic */
	uint64_t cycles;	/* atomic */
};

/*
 * Who owns /sh2000-NAME is decided by a lock on the object itself, not by
 * who created it: the server holds flock(LOCK_EX) on it for its life, and
 * the kernel drops the lock when the server dies, however it dies. So two
 * servers started at once cannot both win, and a dead server's object is
 * taken over (its inode reused) rather than unlinked and created again,
 * which would race with a third. Only the lock's holder ever unlinks the
 * name (sh2000_sim_server_destroy), and only while it still names the
 * holder's object.
 */

/* The object the name refers to now is the one open on fd. */
static int names_fd(const char *shm_name, int fd)
{
	struct stat a, b;
	int fd2 = shm_open(shm_name, O_RDONLY, 0);
	int same;

	if (fd2 < 0)
		return 0;
	same = !fstat(fd, &a) && !fstat(fd2, &b) && a.st_dev == b.st_dev &&
	       a.st_ino == b.st_ino;
	close(fd2);
	return same;
}

/* The pid a live server wrote into its object (0 while it starts). */
static pid_t owner_of(int fd)
{
	struct sh2000_shm *o;
	struct stat sb;
	pid_t pid;

	if (fstat(fd, &sb) || (size_t)sb.st_size < sizeof(*o))
		return 0;
	o = mmap(NULL, sizeof(*o), PROT_READ, MAP_SHARED, fd, 0);
	if (o == MAP_FAILED)
		return 0;
	pid = __atomic_load_n(&o->owner_pid, __ATOMIC_ACQUIRE);
	munmap(o, sizeof(*o));
	return pid;
}

static int refuse(const char *name, int fd, char *msg, size_t len)
{
	pid_t pid = 0;
	int i;

	/* a server that has just won the lock writes its pid at once */
	for (i = 0; i < 100 && pid <= 0; i++) {
		pid = owner_of(fd);
		if (pid <= 0)
			usleep(1000);
	}
	close(fd);
	if (pid > 0)
		return sim_msg(msg, len, -EEXIST, "sim:%s: already served by pid %d",
			       name, (int)pid);
	return sim_msg(msg, len, -EEXIST,
		       "sim:%s: already served (by a server still starting)",
		       name);
}

/* Open /sh2000-NAME, creating it if needed, and take its lock. */
static int claim(struct sh2000_sim_server *s, const char *name, char *msg,
		 size_t len)
{
	int fd, e, tries;

	/* the name can go (its holder's destroy) between open and lock */
	for (tries = 0; tries < 100; tries++) {
		fd = shm_open(s->shm_name, O_RDWR | O_CREAT, 0600);
		if (fd < 0) {
			e = errno;
			return sim_msg(msg, len, -e, "sim:%s: shm_open %s: %s",
				       name, s->shm_name, strerror(e));
		}
		if (flock(fd, LOCK_EX | LOCK_NB) < 0) {
			e = errno;
			if (e == EWOULDBLOCK)
				return refuse(name, fd, msg, len);
			close(fd);
			return sim_msg(msg, len, -e, "sim:%s: lock %s: %s",
				       name, s->shm_name, strerror(e));
		}
		if (names_fd(s->shm_name, fd))
			return fd;
		close(fd);
	}
	return sim_msg(msg, len, -EEXIST, "sim:%s: cannot claim %s", name,
		       s->shm_name);
}

static int map_new(struct sh2000_sim_server *s, const char *name, char *msg,
		   size_t len)
{
	int fd, e;

	fd = claim(s, name, msg, len);
	if (fd < 0)
		return fd;
	if (ftruncate(fd, sizeof(struct sh2000_shm)) < 0) {
		e = errno;
		shm_unlink(s->shm_name);
		close(fd);
		return sim_msg(msg, len, -e, "sim:%s: ftruncate: %s", name,
			       strerror(e));
	}
	s->shm = mmap(NULL, sizeof(struct sh2000_shm), PROT_READ | PROT_WRITE,
		      MAP_SHARED, fd, 0);
	if (s->shm == MAP_FAILED) {
		e = errno;
		s->shm = NULL;
		shm_unlink(s->shm_name);
		close(fd);
		return sim_msg(msg, len, -e, "sim:%s: mmap: %s", name,
			       strerror(e));
	}
	/* a dead server's card goes away before the new one is set up */
	__atomic_store_n(&s->shm->magic, 0, __ATOMIC_RELEASE);
	__atomic_store_n(&s->shm->owner_pid, (int32_t)getpid(),
			 __ATOMIC_RELEASE);
	s->lock_fd = fd;
	return 0;
}

/* Remove the name while it is ours (the lock is held until the close). */
static void unmap(struct sh2000_sim_server *s)
{
	if (names_fd(s->shm_name, s->lock_fd))
		shm_unlink(s->shm_name);
	close(s->lock_fd);
	s->lock_fd = -1;
}

int sh2000_sim_server_create(struct sh2000_sim_server **out, const char *name,
			     const struct sh2000_sim_config *cfg,
			     unsigned int flags, char *msg, size_t len)
{
	struct sh2000_sim_server *s;
	struct sh2000_sim_config def;
	int r;

	*out = NULL;
	if (!name || !*name || strlen(name) > SH2000_SHM_NAME_MAX ||
	    strchr(name, '/'))
		return sim_msg(msg, len, -EINVAL,
				  "sim:%s: bad name (1..%d characters, no '/')",
				  name ? name : "", SH2000_SHM_NAME_MAX);
	s = calloc(1, sizeof(*s));
	if (!s)
		return sim_msg(msg, len, -ENOMEM, "sim:%s: out of memory", name);
	snprintf(s->shm_name, sizeof(s->shm_name), SH2000_SHM_PREFIX "%s", name);
	s->flags = flags;
	pthread_mutex_init(&s->lock, NULL);
	r = map_new(s, name, msg, len);
	if (r < 0) {
		pthread_mutex_destroy(&s->lock);
		free(s);
		return r;
	}
	memset(s->shm, 0, sizeof(*s->shm));
	s->shm->layout = SH2000_SHM_LAYOUT;
	__atomic_store_n(&s->shm->owner_pid, (int32_t)getpid(),
			 __ATOMIC_RELEASE);
	if (!cfg) {
		sh2000_sim_config_default(&def);
		cfg = &def;
	}
	s->ram = s->shm->ram;
	r = sh2000_fw_create(&s->fw, s->ram, cfg);
	if (r < 0) {
		(void)sim_msg(msg, len, r, "sim:%s: card model: %s", name,
			   sh2000_strerror(r));
		munmap(s->shm, sizeof(*s->shm));
		unmap(s);
		pthread_mutex_destroy(&s->lock);
		free(s);
		return r;
	}
	s->shm->servo_period_ns = sh2000_fw_servo_period_ns(s->fw);
	__atomic_store_n(&s->shm->magic, SH2000_SHM_MAGIC, __ATOMIC_RELEASE);
	*out = s;
	return 0;
}

int sh2000_sim_server_attach(struct sh2000_sim_server **out, uint16_t *ram,
			     const struct sh2000_sim_config *cfg,
			     unsigned int flags, char *msg, size_t len)
{
	struct sh2000_sim_server *s;
	int r;

	*out = NULL;
	s = calloc(1, sizeof(*s));
	if (!s)
		return sim_msg(msg, len, -ENOMEM, "attach: out of memory");
	s->flags = flags;
	s->ram = ram;
	pthread_mutex_init(&s->lock, NULL);
	/* a card that boots shows no firmware until it is ready */
	sh2000_dpram_write(ram, SH2000_W_MAGIC, 0);
	r = sh2000_fw_create(&s->fw, ram, cfg);
	if (r < 0) {
		(void)sim_msg(msg, len, r, "card model: %s", sh2000_strerror(r));
		pthread_mutex_destroy(&s->lock);
		free(s);
		return r;
	}
	*out = s;
	return 0;
}

/*
 * How far behind its schedule a server may fall and still catch up: the
 * card's oscillator does not stop when the system deschedules the server,
 * so its cycles per host second stay exact on a loaded machine, and a
 * host that went on pushing points while the server was away finds them
 * taken at the card's own rate (its queue holds up to 64). A host
 * stalled with the server resumes with it and writes its heartbeat
 * within the first replayed cycles (the replay is paced, below), so the
 * replay does not time it out (lib_server_stall stops both for 110 ms,
 * over the host timeout). A second is longer than any scheduler's
 * hiccup: further behind, the server was stopped (SIGSTOP, a suspended
 * machine), and it resumes from now; those cycles are lost.
 */
#define SERVER_CATCH_UP_NS	1000000000ull

/*
 * How fast it catches up: at most this many cycles per servo period, not
 * back to back. A real card never stops, so whatever a served card replays
 * is an artefact of the host's scheduler; replayed in a burst it would
 * take in a few hundred microseconds the points the card would have taken
 * over the whole stall, before the host, descheduled by the same load and
 * catching up its own periods, has sent the next ones, and run the queue
 * dry. Paced, a stall of D catches up in D / (PACE - 1), and a host that
 * catches up within that keeps its queue (docs/cardmodel.md). Two, not
 * four: with two served cards beside LinuxCNC's servo thread and the
 * whole machine stalled 30 ms every 2 s (linuxcnc_drift), the skew
 * between the cards grew by some 20 us a stall to 1 ms at four; at two it
 * stayed under 270 us with the queues at their target. Such stalls still
 * run a queue dry now and then (after 35 s in that run).
 */
#define SERVER_CATCH_UP_PACE	2

/* The schedule of the server's cycles in CLOCK_MONOTONIC ns: when the
 * next cycle is due on the card's oscillator, and when the last began. */
struct sched_state {
	uint64_t due, last;
};

/* Sleep until the next cycle may run (its due time, or a paced step after
 * the last when late), unless stopped; a server further behind than
 * SERVER_CATCH_UP_NS goes on from now. */
static void wait_next(struct sh2000_sim_server *s, struct sched_state *st,
		      uint64_t host_ns)
{
	uint64_t now = sim_mono_ns(), wake = st->due;
	struct timespec ts;

	if (now > st->due + SERVER_CATCH_UP_NS)
		st->due = wake = now;
	else if (now >= st->due && st->last + host_ns / SERVER_CATCH_UP_PACE > wake)
		wake = st->last + host_ns / SERVER_CATCH_UP_PACE;
	if (wake > now) {
		ts.tv_sec = (time_t)(wake / 1000000000ull);
		ts.tv_nsec = (long)(wake % 1000000000ull);
		while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts,
				       NULL) == EINTR &&
		       !__atomic_load_n(&s->stop, __ATOMIC_ACQUIRE))
			;
		now = wake;
	}
	st->last = now;
}

int sh2000_sim_server_run(struct sh2000_sim_server *s)
{
	struct sched_state st = { .due = sim_mono_ns() };

	st.last = st.due;
	if (s->shm)
		__atomic_store_n(&s->shm->running, 1, __ATOMIC_RELEASE);
	while (!__atomic_load_n(&s->stop, __ATOMIC_ACQUIRE)) {
		uint64_t c, host_ns;

		pthread_mutex_lock(&s->lock);
		/* how long this cycle lasts in host time: the card's period
		 * through its oscillator's error */
		host_ns = sh2000_card_cycle(s->fw);
		pthread_mutex_unlock(&s->lock);
		c = __atomic_add_fetch(&s->cycles, 1, __ATOMIC_RELAXED);
		if (s->shm)
			__atomic_store_n(&s->shm->cycles, c, __ATOMIC_RELAXED);
		if (s->flags & SH2000_SIM_SERVER_FREE_RUN)
			continue;
		st.due += host_ns;
		wait_next(s, &st, host_ns);
	}
	if (s->shm)
		__atomic_store_n(&s->shm->running, 0, __ATOMIC_RELEASE);
	return 0;
}

static void *server_thread(void *arg)
{
	sh2000_sim_server_run(arg);
	return NULL;
}

int sh2000_sim_server_start(struct sh2000_sim_server *s)
{
	int r;

	if (s->started)
		return -EBUSY;
	__atomic_store_n(&s->stop, 0, __ATOMIC_RELEASE);
	r = pthread_create(&s->thread, NULL, server_thread, s);
	if (r)
		return -r;
	s->started = 1;
	return 0;
}

void sh2000_sim_server_stop(struct sh2000_sim_server *s)
{
	__atomic_store_n(&s->stop, 1, __ATOMIC_RELEASE);
}

void sh2000_sim_server_destroy(struct sh2000_sim_server *s)
{
	if (!s)
		return;
	sh2000_sim_server_stop(s);
	if (s->started)
		pthread_join(s->thread, NULL);
	sh2000_fw_destroy(s->fw);
	if (s->shm) {
		__atomic_store_n(&s->shm->magic, 0, __ATOMIC_RELEASE);
		munmap(s->shm, sizeof(*s->shm));
		unmap(s);
	} else {
		/* the card goes away: hosts see "no firmware", not a stall */
		sh2000_dpram_write(s->ram, SH2000_W_MAGIC, 0);
	}
	pthread_mutex_destroy(&s->lock);
	free(s);
}

int sh2000_sim_server_inject(struct sh2000_sim_server *s,
			     enum sh2000_inject what, unsigned int axis,
			     unsigned int arg)
{
	int r;

	pthread_mutex_lock(&s->lock);
	r = sh2000_fw_inject(s->fw, what, axis, arg);
	pthread_mutex_unlock(&s->lock);
	return r;
}

int sh2000_sim_server_probe(struct sh2000_sim_server *s,
			    struct sh2000_probe *p)
{
	pthread_mutex_lock(&s->lock);
	sh2000_fw_probe(s->fw, p);
	pthread_mutex_unlock(&s->lock);
	return 0;
}

uint64_t sh2000_sim_server_cycles(struct sh2000_sim_server *s)
{
	return __atomic_load_n(&s->cycles, __ATOMIC_RELAXED);
}

int sh2000_sim_server_set_clock_ppm(struct sh2000_sim_server *s, double ppm)
{
	int r;

	pthread_mutex_lock(&s->lock);
	r = sh2000_fw_set_clock_ppm(s->fw, ppm);
	pthread_mutex_unlock(&s->lock);
	return r < 0 ? -EINVAL : 0;
}

int sh2000_sim_server_set_gantry(struct sh2000_sim_server *s,
				 const struct sh2000_gantry_config *g)
{
	int r;

	pthread_mutex_lock(&s->lock);
	r = sh2000_fw_set_gantry(s->fw, g);
	pthread_mutex_unlock(&s->lock);
	return r < 0 ? -EINVAL : 0;
}

int sh2000_sim_server_set_geometry(struct sh2000_sim_server *s,
				   const struct sh2000_geometry *g)
{
	int r;

	pthread_mutex_lock(&s->lock);
	r = sh2000_fw_set_geometry(s->fw, g);
	pthread_mutex_unlock(&s->lock);
	return r < 0 ? -EINVAL : 0;
}

int sh2000_sim_server_tool_position(struct sh2000_sim_server *s,
				    double tool_mm[SH2000_AXES])
{
	pthread_mutex_lock(&s->lock);
	sh2000_fw_tool_position(s->fw, tool_mm);
	pthread_mutex_unlock(&s->lock);
	return 0;
}

const char *sh2000_sim_server_shm_name(const struct sh2000_sim_server *s)
{
	return s->shm_name;
}
