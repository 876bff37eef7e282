// SPDX-License-Identifier: MIT
/*
 * Sharing one card between programs (docs/library.md "Several programs on
 * one card"). The card has one command slot and one segment ring, so:
 *
 *  - the command lock: one command exchange (write OP..SEQ, wait for the
 *    acknowledgement) at a time across every process. Whoever holds it
 *    takes the next sequence number from the RAM's CMD_SEQ word, so an
 *    answer can only be the holder's own;
 *  - the motion lock: one program at a time streams segments and enables,
 *    disables, homes or resets axes. The holder writes its pid and name
 *    beside the lock so others are told who it is. Programs without it
 *    take the lock shared for the length of such a command, so a claim
 *    never slips in between their check and their command. STOP and the
 *    emergency stop stay open to everyone: stopping only makes safer;
 *  - the bus lock (io: only): the FPGA's address counter is one for all
 *    processes doing port I/O, so a port sequence runs under it.
 *
 * All three are open-file-description locks (F_OFD_SETLK) on bytes of one
 * lock file per card in $SH2000_LOCK_DIR, /run/lock or /tmp. The kernel
 * drops them when the holder closes the card or dies, so a killed process
 * never wedges the card; the next holder re-reads the sequence word. The
 * in-process `sim` card belongs to one handle and needs none of this, and
 * status snapshots are read without any lock.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sh2000_internal.h"

/* Lock bytes, the last command-slot user and the owner record in the lock
 * file. */
#define ARB_TOKEN_OFF	32
#define ARB_INFO_OFF	64
#define ARB_INFO_LEN	64
/* Poll period while another process holds a lock. */
#define ARB_POLL_NS	20000ull

static const char *lock_dir(void)
{
	const char *d = getenv("SH2000_LOCK_DIR");

	if (d && *d)
		return d;
	return access("/run/lock", W_OK) == 0 ? "/run/lock" : "/tmp";
}

int sh2000_arb_open(struct sh2000 *h, const char *id, char *msg, size_t len)
{
	char path[sizeof(h->arb.path)];
	struct stat sb;
	int fd, e;

	if (snprintf(path, sizeof(path), "%s/sh2000-%s.lock", lock_dir(),
		     id) >= (int)sizeof(path))
		return sh2000_msg(msg, len, -ENAMETOOLONG,
				  "%s: lock file name too long", h->device);
	/*
	 * Open it as it is, create it only if it is not there: an O_CREAT
	 * open of a file another user created in a sticky world-writable
	 * folder such as /run/lock fails with EACCES under
	 * fs.protected_regular (Debian's procps sets it to 2), which would
	 * lock every user of the sh2000 group but the first out of the card.
	 */
	fd = open(path, O_RDWR | O_CLOEXEC | O_NOFOLLOW);
	if (fd < 0 && errno == ENOENT)
		fd = open(path, O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW,
			  0666);
	if (fd < 0 && errno == EEXIST)	/* another program was quicker */
		fd = open(path, O_RDWR | O_CLOEXEC | O_NOFOLLOW);
	if (fd < 0) {
		e = errno;
		return sh2000_msg(msg, len, -e,
				  "%s: cannot open the card's lock file %s: %s (every program using the card must be able to write it)",
				  h->device, path, strerror(e));
	}
	/* whoever creates it: every user of the card must be able to lock */
	if (fstat(fd, &sb) == 0 && sb.st_uid == geteuid() &&
	    (sb.st_mode & 0666) != 0666)
		(void)fchmod(fd, 0666);
	h->arb.fd = fd;
	snprintf(h->arb.path, sizeof(h->arb.path), "%s", path);
	/* this handle, among every user the card ever had: never 0 */
	h->arb.token = ((uint64_t)getpid() << 32) ^ sh2000_mono_ns() ^
		       (uint64_t)(uintptr_t)h;
	h->arb.token |= 1;
	return 0;
}

void sh2000_arb_close(struct sh2000 *h)
{
	if (h->arb.fd >= 0)
		close(h->arb.fd);	/* drops every lock of this handle */
	h->arb.fd = -1;
}

static int ofd(struct sh2000 *h, int cmd, short type, unsigned int which)
{
	struct flock fl = {
		.l_type = type,
		.l_whence = SEEK_SET,
		.l_start = which,
		.l_len = 1,
	};

	if (fcntl(h->arb.fd, cmd, &fl) == 0)
		return cmd == F_OFD_GETLK ? fl.l_type != F_UNLCK : 0;
	return -errno;
}

/*
 * Take lock `which` (SH2000_ARB_*) of type F_WRLCK or F_RDLCK, waiting up
 * to timeout_ms (0: try once). Called with h->lock held; it is released
 * while waiting so the handle's other threads go on.
 */
int sh2000_arb_take(struct sh2000 *h, unsigned int which, short type,
		    int timeout_ms)
{
	uint64_t t0 = sh2000_mono_ns();
	int r;

	if (h->arb.fd < 0)
		return 0;
	for (;;) {
		r = ofd(h, F_OFD_SETLK, type, which);
		if (r != -EAGAIN && r != -EACCES)
			break;
		if (sh2000_mono_ns() - t0 >= (uint64_t)timeout_ms * 1000000ull)
			return -EAGAIN;
		pthread_mutex_unlock(&h->lock);
		sh2000_sleep_real(ARB_POLL_NS);
		pthread_mutex_lock(&h->lock);
	}
	if (r < 0)
		return sh2000_fail(h, r, "lock file %s: %s", h->arb.path,
				   strerror(-r));
	return 0;
}

/* Byte of the waiting marker: programs waiting for the command lock hold
 * it shared, so that one that has just released the lock lets them go
 * first instead of taking it again at once (the lock itself is not fair:
 * a busy program would starve the others). */
#define ARB_WAITING	3u
/* A program that released the command lock this recently defers to
 * waiters, for at most ARB_DEFER_NS. */
#define ARB_RECENT_NS	200000ull
#define ARB_DEFER_NS	2000000ull

static void defer_to_waiters(struct sh2000 *h)
{
	uint64_t t0 = sh2000_mono_ns();

	if (!h->arb.dropped_ns || t0 - h->arb.dropped_ns > ARB_RECENT_NS ||
	    ofd(h, F_OFD_GETLK, F_WRLCK, ARB_WAITING) <= 0)
		return;
	/* until one of them has it (or they are gone) */
	while (ofd(h, F_OFD_GETLK, F_WRLCK, SH2000_ARB_CMD) <= 0 &&
	       ofd(h, F_OFD_GETLK, F_WRLCK, ARB_WAITING) > 0 &&
	       sh2000_mono_ns() - t0 < ARB_DEFER_NS) {
		pthread_mutex_unlock(&h->lock);
		sh2000_sleep_real(ARB_POLL_NS / 4);
		pthread_mutex_lock(&h->lock);
	}
}

static int take_cmd(struct sh2000 *h)
{
	int r;

	defer_to_waiters(h);
	r = ofd(h, F_OFD_SETLK, F_WRLCK, SH2000_ARB_CMD);
	if (r != -EAGAIN && r != -EACCES)
		return r;
	/* queue up: others see that someone waits */
	(void)ofd(h, F_OFD_SETLK, F_RDLCK, ARB_WAITING);
	r = sh2000_arb_take(h, SH2000_ARB_CMD, F_WRLCK, SH2000_ARB_WAIT_MS);
	sh2000_arb_drop(h, ARB_WAITING);
	return r;
}

/* Whether another handle used the command slot since this one did (the
 * command lock is held): 1 and this handle marked as the last user, 0. */
static int cmd_taken_over(struct sh2000 *h)
{
	uint64_t last = 0;
	int r;

	if (pread(h->arb.fd, &last, sizeof(last), ARB_TOKEN_OFF) ==
	    (ssize_t)sizeof(last) && last == h->arb.token)
		return 0;
	if (pwrite(h->arb.fd, &h->arb.token, sizeof(h->arb.token),
		   ARB_TOKEN_OFF) != (ssize_t)sizeof(h->arb.token)) {
		r = -errno;
		sh2000_arb_drop(h, SH2000_ARB_CMD);
		return sh2000_fail(h, r ? r : -EIO, "lock file %s: %s",
				   h->arb.path, strerror(r ? -r : EIO));
	}
	return 1;
}

/*
 * The command lock. Returns 1 if another handle used the command slot
 * since this one last did (then the caller re-reads CMD_SEQ from the RAM,
 * whoever wrote it last), 0 if this handle was the last (its own sequence
 * number is current: no extra port cycles for a program alone), or an
 * error.
 */
int sh2000_arb_cmd_take(struct sh2000 *h)
{
	int r;

	if (h->arb.fd < 0)
		return 0;
	r = take_cmd(h);
	return r < 0 ? r : cmd_taken_over(h);
}

int sh2000_arb_cmd_try(struct sh2000 *h)
{
	int r;

	if (h->arb.fd < 0)
		return 0;
	r = ofd(h, F_OFD_SETLK, F_WRLCK, SH2000_ARB_CMD);
	if (r == -EACCES)
		r = -EAGAIN;
	return r < 0 ? r : cmd_taken_over(h);
}

void sh2000_arb_drop(struct sh2000 *h, unsigned int which)
{
	if (h->arb.fd < 0)
		return;
	(void)ofd(h, F_OFD_SETLK, F_UNLCK, which);
	if (which == SH2000_ARB_CMD)
		h->arb.dropped_ns = sh2000_mono_ns();
}

/* "sh2000-upload (pid 1234)" of the motion lock's holder, or "". */
static void holder(struct sh2000 *h, char *buf, size_t len)
{
	char info[ARB_INFO_LEN + 1];
	ssize_t n = pread(h->arb.fd, info, ARB_INFO_LEN, ARB_INFO_OFF);
	unsigned int pid;
	char comm[32];

	buf[0] = 0;
	if (n <= 0)
		return;
	info[n] = 0;
	if (sscanf(info, "%u %31s", &pid, comm) == 2)
		snprintf(buf, len, "%s (pid %u)", comm, pid);
}

static void write_holder(struct sh2000 *h)
{
	char info[ARB_INFO_LEN], comm[32] = "?";
	FILE *f = fopen("/proc/self/comm", "re");

	if (f) {
		if (fscanf(f, "%31s", comm) != 1)
			snprintf(comm, sizeof(comm), "?");
		fclose(f);
	}
	memset(info, 0, sizeof(info));
	snprintf(info, sizeof(info), "%u %s\n", (unsigned int)getpid(), comm);
	(void)pwrite(h->arb.fd, info, sizeof(info), ARB_INFO_OFF);
}

static int owned_elsewhere(struct sh2000 *h, const char *what)
{
	char who[96];

	holder(h, who, sizeof(who));
	return sh2000_fail(h, -SH2000_EOWNED,
			   "%s: the motion is held by %s; it has to finish or close the card first",
			   what, *who ? who : "another program");
}

/* The motion lock for this handle: 1 newly taken (the holder record
 * written), 0 held already or no lock file, < 0 an error. */
int sh2000_arb_claim_locked(struct sh2000 *h)
{
	int r;

	if (h->arb.fd < 0 || h->arb.motion)
		return 0;
	/* others hold it shared only for one command: wait that long */
	r = sh2000_arb_take(h, SH2000_ARB_MOTION, F_WRLCK, SH2000_CMD_TIMEOUT_MS);
	if (r == -EAGAIN)
		return owned_elsewhere(h, "taking the motion");
	if (r < 0)
		return r;
	h->arb.motion = 1;
	write_holder(h);
	return 1;
}

int sh2000_arb_holds_motion(const struct sh2000 *h)
{
	return h->arb.fd >= 0 && h->arb.motion;
}

void sh2000_arb_release_locked(struct sh2000 *h)
{
	if (sh2000_arb_holds_motion(h)) {
		char none[ARB_INFO_LEN] = { 0 };

		(void)pwrite(h->arb.fd, none, sizeof(none), ARB_INFO_OFF);
		sh2000_arb_drop(h, SH2000_ARB_MOTION);
	}
	h->arb.motion = 0;
}

int sh2000_arb_motion_begin(struct sh2000 *h, const char *what)
{
	int r;

	if (h->arb.fd < 0 || h->arb.motion)
		return 0;
	r = sh2000_arb_take(h, SH2000_ARB_MOTION, F_RDLCK, 0);
	if (r == -EAGAIN)
		return owned_elsewhere(h, what);
	return r;
}

void sh2000_arb_motion_end(struct sh2000 *h)
{
	if (h->arb.fd >= 0 && !h->arb.motion)
		sh2000_arb_drop(h, SH2000_ARB_MOTION);
}

int sh2000_motion_holder(struct sh2000 *h, char *buf, size_t len)
{
	int r = 0;

	if (!buf || !len)
		return -EINVAL;
	buf[0] = 0;
	pthread_mutex_lock(&h->lock);
	if (h->arb.fd >= 0 && h->arb.motion) {
		holder(h, buf, len);
		r = 1;
	} else if (h->arb.fd >= 0 &&
		   /* a read lock conflicts with the holder's only, not with
		    * other programs' one-command shared locks */
		   ofd(h, F_OFD_GETLK, F_RDLCK, SH2000_ARB_MOTION) > 0) {
		holder(h, buf, len);
		if (!*buf)
			snprintf(buf, len, "another program");
		r = 1;
	}
	pthread_mutex_unlock(&h->lock);
	return r;
}

/* io: one port sequence at a time across processes. Held for a few
 * microseconds, so the wait keeps the handle's lock. */
int sh2000_arb_bus_take(struct sh2000 *h)
{
	uint64_t t0 = sh2000_mono_ns();
	int r;

	if (h->arb.fd < 0)
		return 0;
	while ((r = ofd(h, F_OFD_SETLK, F_WRLCK, SH2000_ARB_BUS)) == -EAGAIN ||
	       r == -EACCES) {
		/* a real-time call does not wait: its caller tries again
		 * next tick */
		if (h->nb.active)
			return -EAGAIN;
		if (sh2000_mono_ns() - t0 > SH2000_ARB_WAIT_MS * 1000000ull)
			return sh2000_fail(h, -SH2000_ETIMEOUT,
					   "another program has held the card's port registers for over %d ms (lock file %s)",
					   SH2000_ARB_WAIT_MS, h->arb.path);
		sh2000_sleep_real(ARB_POLL_NS);
	}
	if (r < 0)
		return sh2000_fail(h, r, "lock file %s: %s", h->arb.path,
				   strerror(-r));
	return 0;
}
