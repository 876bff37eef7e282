/* SPDX-License-Identifier: MIT */
/*
 * Two servers started on one name at the same instant (two processes
 * released by one pipe), many times: exactly one serves, the other is told
 * who does, the name refers to the winner's object while it serves and is
 * gone once it stops. The same when the name holds an object a killed
 * server left behind. Separate processes: the server's lock belongs to the
 * process, as sh2000-sim's does.
 */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "simtest.h"
#include "sh2000_shm.h"

#define ROUNDS	200

struct racer {
	pid_t pid;
	int result;	/* read end: "1" served, "0<msg>" refused */
	int release;	/* write end: the winner stops when it closes */
};

/* A child: wait for the start, create, report, serve until released. */
static void race_child(const char *n, int start, int result, int release)
{
	struct sh2000_sim_server *s = NULL;
	char msg[256], buf[260], c;
	int r;

	(void)!read(start, &c, 1);	/* EOF: go */
	r = sh2000_sim_server_create(&s, n, NULL, 0, msg, sizeof(msg));
	snprintf(buf, sizeof(buf), "%c%s", r == 0 ? '1' : '0',
		 r == 0 ? "" : msg);
	(void)!write(result, buf, strlen(buf));
	close(result);
	if (r == 0) {
		(void)!read(release, &c, 1);
		sh2000_sim_server_destroy(s);
	}
	_exit(r == 0 ? 0 : 3);
}

static void spawn(struct racer *rc, const char *n, int start_rd,
		  int start_wr)
{
	int res[2], rel[2];

	if (pipe(res) || pipe(rel))
		fail_msg("pipe: %s", strerror(errno));
	rc->pid = fork();
	if (rc->pid < 0)
		fail_msg("fork: %s", strerror(errno));
	if (rc->pid == 0) {
		close(start_wr);
		close(res[0]);
		close(rel[1]);
		race_child(n, start_rd, res[1], rel[0]);
	}
	close(res[1]);
	close(rel[0]);
	rc->result = res[0];
	rc->release = rel[1];
}

static int32_t owner_pid(const char *shm_name)
{
	struct sh2000_shm *m;
	int32_t pid;
	int fd = shm_open(shm_name, O_RDONLY, 0);

	if (fd < 0)
		return -1;
	m = mmap(NULL, sizeof(*m), PROT_READ, MAP_SHARED, fd, 0);
	close(fd);
	if (m == MAP_FAILED)
		return -1;
	pid = m->owner_pid;
	munmap(m, sizeof(*m));
	return pid;
}

/* An object as a server killed with SIGKILL leaves it: owner gone. */
static void leave_stale(const char *shm_name)
{
	struct sh2000_shm *m;
	int fd = shm_open(shm_name, O_RDWR | O_CREAT | O_EXCL, 0600);

	assert_true(fd >= 0);
	assert_int_equal(ftruncate(fd, sizeof(*m)), 0);
	m = mmap(NULL, sizeof(*m), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
	close(fd);
	assert_true(m != MAP_FAILED);
	m->magic = SH2000_SHM_MAGIC;
	m->layout = SH2000_SHM_LAYOUT;
	m->owner_pid = 0x7ffffff0;	/* no such process */
	munmap(m, sizeof(*m));
}

/* One round: returns the index of the winner. */
static unsigned int race(const char *n, const char *shm_name, int stale)
{
	struct racer rc[2];
	char buf[2][260];
	unsigned int i, wins = 0, winner = 0;
	int go[2], st;
	ssize_t k;

	if (stale)
		leave_stale(shm_name);
	if (pipe(go))
		fail_msg("pipe: %s", strerror(errno));
	for (i = 0; i < 2; i++)
		spawn(&rc[i], n, go[0], go[1]);
	close(go[0]);
	close(go[1]);		/* both start now */
	for (i = 0; i < 2; i++) {
		k = read(rc[i].result, buf[i], sizeof(buf[i]) - 1);
		buf[i][k > 0 ? k : 0] = '\0';
		close(rc[i].result);
		if (buf[i][0] == '1') {
			wins++;
			winner = i;
		}
	}
	if (wins != 1)
		fail_msg("%u servers won (%s | %s)", wins, buf[0], buf[1]);
	/* the loser was told who serves; the name is the winner's */
	if (!strstr(buf[!winner], "already served"))
		fail_msg("loser's message: %s", buf[!winner] + 1);
	assert_int_equal(waitpid(rc[!winner].pid, &st, 0), rc[!winner].pid);
	assert_int_equal(WEXITSTATUS(st), 3);
	assert_int_equal(owner_pid(shm_name), rc[winner].pid);
	close(rc[!winner].release);
	close(rc[winner].release);
	assert_int_equal(waitpid(rc[winner].pid, &st, 0), rc[winner].pid);
	assert_int_equal(WEXITSTATUS(st), 0);
	/* the winner removed its name, and nobody had removed it before */
	assert_int_equal(owner_pid(shm_name), -1);
	return winner;
}

static void race_many(int stale)
{
	char n[64], shm_name[96];
	unsigned int round, first = 0;

	snprintf(n, sizeof(n), "race%s-%d", stale ? "stale" : "", (int)getpid());
	snprintf(shm_name, sizeof(shm_name), SH2000_SHM_PREFIX "%s", n);
	shm_unlink(shm_name);
	for (round = 0; round < ROUNDS; round++)
		first += race(n, shm_name, stale) == 0;
	print_message("%u rounds: the first-forked server won %u\n", ROUNDS,
		      first);
}

static void test_race_fresh(void **state)
{
	(void)state;
	race_many(0);
}

static void test_race_stale(void **state)
{
	(void)state;
	race_many(1);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_race_fresh),
		cmocka_unit_test(test_race_stale),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
