// SPDX-License-Identifier: MIT
/*
 * Compensation tables through the binding (docs/compensation.md): load a
 * table file, the active tables' status, clear them. The file's rules and
 * messages (FILE:LINE) are the library's.
 */
#include "binding.h"
#include "card_methods.h"

/* comp_load(path): sh2000_comp_load_file. */
PyObject *sh2k_card_comp_load(PyCard *c, PyObject *args)
{
	struct sh2000 *h = sh2k_handle(c);
	const char *path;
	int r;

	if (!h || !PyArg_ParseTuple(args, "s", &path))
		return NULL;
	SH2K_CALL(c, r = sh2000_comp_load_file(h, path));
	if (r < 0)
		return sh2k_raise(r, h, NULL, NULL);
	Py_RETURN_NONE;
}

PyObject *sh2k_card_comp_clear(PyCard *c, PyObject *unused)
{
	struct sh2000 *h = sh2k_handle(c);
	int r;

	(void)unused;
	if (!h)
		return NULL;
	SH2K_CALL(c, r = sh2000_comp_clear(h));
	if (r < 0)
		return sh2k_raise(r, h, NULL, NULL);
	Py_RETURN_NONE;
}

/* comp_status(): {state, tables, id, sum, generation}. */
PyObject *sh2k_card_comp_status(PyCard *c, PyObject *unused)
{
	struct sh2000 *h = sh2k_handle(c);
	struct sh2000_comp_status st;
	int r;

	(void)unused;
	if (!h)
		return NULL;
	SH2K_CALL(c, r = sh2000_comp_status(h, &st));
	if (r < 0)
		return sh2k_raise(r, h, NULL, NULL);
	return Py_BuildValue("{s:I,s:I,s:k,s:k,s:I}", "state", st.state,
			     "tables", st.tables, "id", (unsigned long)st.id,
			     "sum", (unsigned long)st.sum, "generation",
			     st.generation);
}
