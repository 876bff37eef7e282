/* SPDX-License-Identifier: MIT */
/*
 * jsonq: the tools tests' JSON reader (json-c, strict). Reads JSON values
 * from stdin, one per line; for each line prints the values at the given
 * JSON pointers (RFC 6901, e.g. /axes/0/cmd_mm), tab-separated: strings
 * raw, numbers %.17g, arrays and objects as JSON. Exit 1 if a line is not
 * strict JSON or a pointer is missing, 2 on usage.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <json-c/json.h>
#include <json-c/json_pointer.h>

static void print_value(json_object *v)
{
	switch (json_object_get_type(v)) {
	case json_type_null:
		fputs("null", stdout);
		break;
	case json_type_string:
		fputs(json_object_get_string(v), stdout);
		break;
	case json_type_double:
		printf("%.17g", json_object_get_double(v));
		break;
	case json_type_int:
		printf("%lld", (long long)json_object_get_int64(v));
		break;
	default:
		fputs(json_object_to_json_string_ext(v, JSON_C_TO_STRING_PLAIN), stdout);
		break;
	}
}

int main(int argc, char **argv)
{
	char *line = NULL;
	size_t cap = 0;
	int n = 0;

	if (argc < 1)
		return 2;
	while (getline(&line, &cap, stdin) >= 0) {
		struct json_tokener *tok = json_tokener_new();
		json_object *o;
		size_t len = strlen(line);

		n++;
		while (len && (line[len - 1] == '\n' || line[len - 1] == '\r'))
			line[--len] = '\0';
		json_tokener_set_flags(tok, JSON_TOKENER_STRICT);
		o = json_tokener_parse_ex(tok, line, (int)len);
		if (!o || json_tokener_get_error(tok) != json_tokener_success ||
		    json_tokener_get_parse_end(tok) != len) {
			fprintf(stderr, "jsonq: line %d is not one strict JSON value: %s\n",
				n, line);
			json_tokener_free(tok);
			return 1;
		}
		json_tokener_free(tok);
		for (int i = 1; i < argc; i++) {
			json_object *v = NULL;

			if (json_pointer_get(o, argv[i], &v) != 0) {
				fprintf(stderr, "jsonq: line %d has no %s\n", n, argv[i]);
				json_object_put(o);
				return 1;
			}
			if (i > 1)
				putchar('\t');
			print_value(v);
		}
		putchar('\n');
		json_object_put(o);
	}
	free(line);
	if (!n) {
		fprintf(stderr, "jsonq: no input\n");
		return 1;
	}
	return 0;
}
