// SPDX-License-Identifier: MIT
/* Planes and their axis order (sh2000/geometry.h): the one table. */
#include <errno.h>

#include "sh2000/geometry.h"

int sh2000_plane_axes(enum sh2000_plane plane, unsigned int *first,
		      unsigned int *second, unsigned int *normal)
{
	/* right-handed (first, second, normal), as RS274NGC's G17..G19 */
	static const unsigned int axes[3][3] = {
		{ 0, 1, 2 },	/* G17: X Y, normal Z */
		{ 2, 0, 1 },	/* G18: Z X, normal Y */
		{ 1, 2, 0 },	/* G19: Y Z, normal X */
	};
	unsigned int i;

	if (plane < SH2000_PLANE_XY || plane > SH2000_PLANE_YZ)
		return -EINVAL;
	i = (unsigned int)plane - SH2000_PLANE_XY;
	*first = axes[i][0];
	*second = axes[i][1];
	*normal = axes[i][2];
	return 0;
}

const char *sh2000_plane_name(enum sh2000_plane plane)
{
	switch (plane) {
	case SH2000_PLANE_XY:
		return "XY";
	case SH2000_PLANE_XZ:
		return "XZ";
	case SH2000_PLANE_YZ:
		return "YZ";
	}
	return "?";
}
