/* SPDX-License-Identifier: MIT */
/*
 * Permissions: a program that may not open the card is told why, in terms
 * of the sh2000 group and the udev rule that gives the card to it
 * (60-sh2000.rules), and io: without CAP_SYS_RAWIO says it needs it.
 *
 * Runs unprivileged or as root. As root the program under test is a child
 * that drops to nobody (uid and gid 65534, no supplementary groups, no
 * capabilities) and opens a root:root 0660 file, as a user outside the
 * group meets /dev/sh2000-N; if the system has a group sh2000, the file
 * is also given to it, as the udev rule does: nobody is told to join the
 * group, and with the group added the permission check passes. As another
 * user the file is mode 0000. The VM suite (tests/kernel) does the same on
 * a real /dev/sh2000-0.
 */
#include <errno.h>
#include <fcntl.h>
#include <grp.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "simtest.h"

#define NOBODY	65534

struct result {
	int r;
	char msg[512];
};

/* sh2000_open(dev) as nobody (in a child) when root, else here; extra:
 * a supplementary group for the child, or (gid_t)-1. */
static struct result open_as_user(const char *dev, gid_t extra)
{
	struct result res = { 0 };
	struct sh2000 *h = NULL;
	int fds[2], st;
	pid_t p;

	if (geteuid() != 0) {
		res.r = sh2000_open(&h, dev, res.msg, sizeof(res.msg));
		sh2000_close(h);
		return res;
	}
	assert_int_equal(pipe(fds), 0);
	p = fork();
	assert_true(p >= 0);
	if (p == 0) {
		gid_t groups[1] = { extra };

		if (setgroups(extra == (gid_t)-1 ? 0 : 1, groups) < 0 ||
		    setgid(NOBODY) < 0 || setuid(NOBODY) < 0)
			_exit(3);
		res.r = sh2000_open(&h, dev, res.msg, sizeof(res.msg));
		sh2000_close(h);
		_exit(write(fds[1], &res, sizeof(res)) == sizeof(res) ? 0 : 2);
	}
	close(fds[1]);
	assert_int_equal(read(fds[0], &res, sizeof(res)), (ssize_t)sizeof(res));
	close(fds[0]);
	assert_int_equal(waitpid(p, &st, 0), p);
	assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
	return res;
}

static void has(const struct result *res, const char *needle)
{
	if (!strstr(res->msg, needle))
		fail_msg("message \"%s\" lacks \"%s\"", res->msg, needle);
}

/* A file standing in for /dev/sh2000-N in a folder anyone may enter. */
static void make_node(char *dir, char *path, size_t len)
{
	int fd;

	assert_non_null(mkdtemp(dir));
	assert_int_equal(chmod(dir, 0755), 0);
	snprintf(path, len, "%s/sh2000-0", dir);
	fd = open(path, O_CREAT | O_WRONLY, 0600);
	assert_true(fd >= 0);
	close(fd);
	/* root:root 0660 as the rule leaves it without the group; mode 0000
	 * for a user who owns it */
	assert_int_equal(chmod(path, geteuid() == 0 ? 0660 : 0), 0);
}

static void test_dev_outside_group(void **state)
{
	char dir[] = "/tmp/sh2000-perm-XXXXXX", path[128];
	struct group *g = getgrnam("sh2000");
	struct result res;

	(void)state;
	make_node(dir, path, sizeof(path));
	res = open_as_user(path, (gid_t)-1);
	printf("%s\n", res.msg);
	assert_int_equal(res.r, -EACCES);
	has(&res, path);
	has(&res, "Permission denied");
	has(&res, "group sh2000");
	has(&res, "udev rule 60-sh2000.rules");
	if (!g)
		has(&res, "there is no group sh2000: sudo groupadd --system sh2000");
	else if (geteuid() == 0)
		has(&res, "it is group root, mode 0660, not group sh2000");

	if (g && geteuid() == 0) {
		/* what the rule does: the group's, 0660 */
		assert_int_equal(chown(path, 0, g->gr_gid), 0);
		assert_int_equal(chmod(path, 0660), 0);
		res = open_as_user(path, (gid_t)-1);
		printf("%s\n", res.msg);
		assert_int_equal(res.r, -EACCES);
		has(&res, "it belongs to group sh2000 (udev rule 60-sh2000.rules) and this user is not in it: sudo usermod -aG sh2000 $USER");
		/* a member gets past the permission check to the next one:
		 * a plain file is no card */
		res = open_as_user(path, g->gr_gid);
		printf("%s\n", res.msg);
		assert_int_equal(res.r, -ENODEV);
		has(&res, "not an sh2000 device");
	}
	assert_int_equal(unlink(path), 0);
	assert_int_equal(rmdir(dir), 0);
}

static void test_io_without_rawio(void **state)
{
	struct result res;

	(void)state;
#if defined(__x86_64__) || defined(__i386__)
	/* nobody has no capabilities; the port is never touched */
	res = open_as_user("io:0x300", (gid_t)-1);
	printf("%s\n", res.msg);
	assert_int_equal(res.r, -EPERM);
	has(&res, "io:0x300");
	has(&res, "needs CAP_SYS_RAWIO");
#else
	res = open_as_user("io:0x300", (gid_t)-1);
	assert_int_equal(res.r, -EOPNOTSUPP);
#endif
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_dev_outside_group),
		cmocka_unit_test(test_io_without_rawio),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
