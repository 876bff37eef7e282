// SPDX-License-Identifier: MIT
/*
 * An output file's folder checked before anything moves: a typo in
 * --plot, --trace or --save is a usage error found before the run, not a
 * failure found after it (the machine moved for nothing).
 */
#include <errno.h>
#include <string.h>
#include <unistd.h>

#include "toolcommon.h"

int sh2000_tool_writable(const char *opt, const char *path)
{
	char dir[4096];
	const char *slash;

	if (!path)
		return 0;
	slash = strrchr(path, '/');
	if (!slash) {
		strcpy(dir, ".");
	} else if (slash == path) {
		strcpy(dir, "/");
	} else {
		size_t n = (size_t)(slash - path);

		if (n >= sizeof(dir))
			return sh2000_tool_usage(NULL, "%s: the path is too long", opt);
		memcpy(dir, path, n);
		dir[n] = 0;
	}
	if (access(dir, W_OK) < 0)
		return sh2000_tool_usage(NULL, "%s %s: cannot write in %s: %s (nothing moved)",
					 opt, path, dir, strerror(errno));
	return 0;
}
