/* SPDX-License-Identifier: MIT */
/*
 * The parameter file's lines as `sh2000ctl params save` writes them and
 * `params load` reads them (tools/ctl/params_plan.h has the format), for
 * every tool that writes one (sh2000ctl, sh2000-tune --save).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "toolcommon.h"

void sh2000_tool_param_format(char *buf, size_t len, unsigned int id, double v)
{
	const struct sh2000_param_info *pi = sh2000_param_lookup(id);
	int f32 = pi && pi->type == SH2000_PT_F32, prec = 1;

	/* a shortest text that reads back as v: exactly, or for a binary32
	 * parameter as the same float (the card keeps floats); no exponent
	 * for whole numbers that have one */
	if (fabs(v) >= 1 && fabs(v) < 1e17)
		prec = (int)floor(log10(fabs(v))) + 1;
	for (; prec <= 17; prec++) {
		double back;

		snprintf(buf, len, "%.*g", prec, v);
		back = strtod(buf, NULL);
		if (back == v || (f32 && (float)back == (float)v))
			return;
	}
}

void sh2000_tool_param_line(FILE *f, unsigned int id, double v)
{
	char val[64], lhs[160];

	sh2000_tool_param_format(val, sizeof(val), id, v);
	snprintf(lhs, sizeof(lhs), "%s = %s", sh2000_param_name(id), val);
	if (id == SH2000_P_DAC_RANGE)
		fprintf(f, "%-32s # 0: 0..5 V, 1: 0..10 V, 2: +-5 V, 3: +-10 V\n",
			lhs);
	else
		fprintf(f, "%-32s # %s\n", lhs, sh2000_param_unit(id));
}
