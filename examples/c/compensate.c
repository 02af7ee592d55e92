/*
 * compensate: a host program in C99 over the hyst C API (include/hyst.h).
 *
 *   compensate MODEL.toml [--column NAME] [--direct] < in.csv > out.csv
 *
 * Reads a CSV table with a header row on stdin, runs the fitted model's exact inverse (desired
 * output in, command out: the feed-forward compensation of the modelled hysteresis; with
 * --direct the model itself: input in, output out) over one column as one record, and writes the CSV `x,y` to stdout: x the input sample, y
 * the result. The output is byte for byte that of
 *
 *   hyst run --model MODEL.toml [--inverse] --column NAME in.csv -o out.csv
 *
 * Column: --column NAME, else a column called `x`, else the only column. (The C API does not
 * expose the model file's column names, so unlike `hyst run --model` there is no default taken
 * from the model: give --column when the table has several columns.)
 *
 * The CSV is read as hyst-io reads it: blank lines and lines starting with `#` are skipped but
 * counted, cells are trimmed of spaces and tabs, `"quoted"` cells, CRLF and a UTF-8 BOM are
 * accepted, every cell of every row must be a finite number (the whole table is checked, not
 * only the chosen column).
 *
 * Numbers are written as hyst-io writes them: the shortest decimal that parses back to the
 * identical double (so the text round-trips exactly, like %.17g, but is also identical to the
 * CLI's), in plain notation for magnitudes in [1e-5, 1e16) and as `1.5e-7` otherwise.
 *
 * Errors go to stderr, naming the line and column (`<stdin>:LINE: column C ("name"): ...`),
 * with exit status 1 (2 for a usage error); nothing is written to stdout then.
 */

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hyst.h"

#define SOURCE "<stdin>"

static const char *program = "compensate";

static void fail(const char *format, ...)
{
    va_list args;
    fprintf(stderr, "%s: ", program);
    va_start(args, format);
    vfprintf(stderr, format, args);
    va_end(args);
    fputc('\n', stderr);
}

static void usage(FILE *to)
{
    fprintf(to,
            "usage: %s MODEL.toml [--column NAME] [--direct] < in.csv > out.csv\n"
            "  runs the model's exact inverse (desired output in, command out; --direct: the\n"
            "  model itself) over the column NAME (default: `x`, or the only column) and writes\n"
            "  `x,y`\n",
            program);
}

/* ------------------------------------------------------------------------------------------ */
/* Growing buffers. */

typedef struct {
    double *data;
    size_t len, cap;
} doubles;

static int doubles_push(doubles *d, double v)
{
    if (d->len == d->cap) {
        size_t cap = d->cap ? 2 * d->cap : 1024;
        double *data = (double *)realloc(d->data, cap * sizeof *data);
        if (!data)
            return -1;
        d->data = data;
        d->cap = cap;
    }
    d->data[d->len++] = v;
    return 0;
}

typedef struct {
    size_t *data;
    size_t len, cap;
} sizes;

static int sizes_push(sizes *s, size_t v)
{
    if (s->len == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 1024;
        size_t *data = (size_t *)realloc(s->data, cap * sizeof *data);
        if (!data)
            return -1;
        s->data = data;
        s->cap = cap;
    }
    s->data[s->len++] = v;
    return 0;
}

typedef struct {
    char *data;
    size_t len, cap;
} bytes;

static int bytes_push(bytes *b, char c)
{
    if (b->len == b->cap) {
        size_t cap = b->cap ? 2 * b->cap : 256;
        char *data = (char *)realloc(b->data, cap);
        if (!data)
            return -1;
        b->data = data;
        b->cap = cap;
    }
    b->data[b->len++] = c;
    return 0;
}

/* Reads the whole stream (NUL-terminated, the length without the NUL in *len). */
static char *read_all(FILE *f, size_t *len)
{
    bytes b = {NULL, 0, 0};
    char chunk[65536];
    size_t got;
    while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) {
        if (b.cap - b.len < got) {
            size_t cap = 2 * (b.len + got);
            char *data = (char *)realloc(b.data, cap);
            if (!data) {
                free(b.data);
                return NULL;
            }
            b.data = data;
            b.cap = cap;
        }
        memcpy(b.data + b.len, chunk, got);
        b.len += got;
    }
    if (ferror(f) || bytes_push(&b, '\0') != 0) {
        free(b.data);
        return NULL;
    }
    *len = b.len - 1;
    return b.data;
}

/* ------------------------------------------------------------------------------------------ */
/* CSV records, as the csv crate reads them for hyst-io: fields separated by `,`, records ended
 * by `\n`, `\r\n` or `\r`, `"` quoting at the start of a field (`""` inside for a quote), empty
 * lines and lines starting with `#` skipped. Line numbers count `\n`. */

typedef struct {
    const char *text;
    size_t len, pos;
    size_t line; /* the line at `pos` */
} reader;

typedef struct {
    char **cells; /* each trimmed, NUL-terminated */
    size_t count, cap;
    size_t line; /* the line of the record's first byte */
} record;

static void record_clear(record *r)
{
    size_t i;
    for (i = 0; i < r->count; i++)
        free(r->cells[i]);
    r->count = 0;
}

static void record_free(record *r)
{
    record_clear(r);
    free(r->cells);
    r->cells = NULL;
    r->cap = 0;
}

static int is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

/* Appends the cell in `b` (trimmed) to `r`; -1 when out of memory. */
static int record_push(record *r, bytes *b)
{
    size_t start = 0, end = b->len;
    char *cell;
    while (start < end && is_space(b->data[start]))
        start++;
    while (end > start && is_space(b->data[end - 1]))
        end--;
    if (r->count == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 8;
        char **cells = (char **)realloc(r->cells, cap * sizeof *cells);
        if (!cells)
            return -1;
        r->cells = cells;
        r->cap = cap;
    }
    cell = (char *)malloc(end - start + 1);
    if (!cell)
        return -1;
    if (end > start)
        memcpy(cell, b->data + start, end - start);
    cell[end - start] = '\0';
    r->cells[r->count++] = cell;
    b->len = 0;
    return 0;
}

static char reader_take(reader *rd)
{
    char c = rd->text[rd->pos++];
    if (c == '\n')
        rd->line++;
    return c;
}

/* Reads the next record that is not blank. Returns 1 with a record, 0 at the end, -1 when out
 * of memory. */
static int next_record(reader *rd, record *r, bytes *cell)
{
    for (;;) {
        int quoted = 0, at_field_start = 1;
        size_t i;
        int blank;
        /* Skip empty lines and comment lines. */
        while (rd->pos < rd->len) {
            char c = rd->text[rd->pos];
            if (c == '\n' || c == '\r') {
                reader_take(rd);
            } else if (c == '#') {
                while (rd->pos < rd->len && rd->text[rd->pos] != '\n')
                    reader_take(rd);
            } else {
                break;
            }
        }
        if (rd->pos >= rd->len)
            return 0;
        record_clear(r);
        cell->len = 0;
        r->line = rd->line;
        while (rd->pos < rd->len) {
            char c = reader_take(rd);
            if (quoted) {
                if (c == '"') {
                    if (rd->pos < rd->len && rd->text[rd->pos] == '"') {
                        reader_take(rd);
                        if (bytes_push(cell, '"') != 0)
                            return -1;
                    } else {
                        quoted = 0;
                    }
                } else if (bytes_push(cell, c) != 0) {
                    return -1;
                }
                continue;
            }
            if (c == '"' && at_field_start) {
                quoted = 1;
                at_field_start = 0;
            } else if (c == ',') {
                if (record_push(r, cell) != 0)
                    return -1;
                at_field_start = 1;
            } else if (c == '\n' || c == '\r') {
                if (c == '\r' && rd->pos < rd->len && rd->text[rd->pos] == '\n')
                    reader_take(rd);
                break;
            } else {
                if (bytes_push(cell, c) != 0)
                    return -1;
                at_field_start = 0;
            }
        }
        if (record_push(r, cell) != 0)
            return -1;
        /* A line of whitespace only is skipped too. */
        blank = r->count == 1;
        for (i = 0; blank && r->cells[0][i]; i++)
            blank = is_space(r->cells[0][i]);
        if (!blank)
            return 1;
    }
}

/* ------------------------------------------------------------------------------------------ */
/* Numbers. */

/* Parses a cell as Rust's f64::from_str does: [+-] then digits with an optional `.` (at least
 * one digit) and an optional exponent, or inf / infinity / nan. Returns 0 with a finite value,
 * 1 for a number that is not finite (nan, inf, 1e999), -1 for text that is not a number. */
static int parse_number(const char *s, double *value)
{
    const char *p = s, *word;
    size_t digits = 0;
    char *end;
    if (*p == '+' || *p == '-')
        p++;
    word = p;
    {
        /* inf, infinity, nan in any case, as Rust accepts them. */
        char lower[16];
        size_t i;
        for (i = 0; word[i] && i + 1 < sizeof lower; i++)
            lower[i] = (char)((word[i] >= 'A' && word[i] <= 'Z') ? word[i] - 'A' + 'a' : word[i]);
        lower[i] = '\0';
        if (!word[i] &&
            (strcmp(lower, "inf") == 0 || strcmp(lower, "infinity") == 0 || strcmp(lower, "nan") == 0))
            return 1;
    }
    while (*p >= '0' && *p <= '9') {
        p++;
        digits++;
    }
    if (*p == '.') {
        p++;
        while (*p >= '0' && *p <= '9') {
            p++;
            digits++;
        }
    }
    if (digits == 0)
        return -1;
    if (*p == 'e' || *p == 'E') {
        size_t exp_digits = 0;
        p++;
        if (*p == '+' || *p == '-')
            p++;
        while (*p >= '0' && *p <= '9') {
            p++;
            exp_digits++;
        }
        if (exp_digits == 0)
            return -1;
    }
    if (*p != '\0')
        return -1;
    *value = strtod(s, &end); /* correctly rounded, as Rust's parse */
    if (*end != '\0')
        return -1;
    return isfinite(*value) ? 0 : 1;
}

/* Whether a lies exactly halfway between two p-digit decimals and printf's p-digit rounding
 * `d` is the lower one: a's exact expansion (a double has at most 767 significant digits, and
 * glibc prints them exactly) is the p digits of d, a 5, then zeros. */
static int is_tie_below(double a, int p, uint64_t d)
{
    static char exact[900];
    const char *c;
    uint64_t head = 0;
    int k = 0;
    /* Cheap test first: a tie's p + 1 digits are exact and end in 5. */
    snprintf(exact, sizeof exact, "%.*e", p, a);
    if (strchr(exact, 'e')[-1] != '5')
        return 0;
    snprintf(exact, sizeof exact, "%.*e", 800, a);
    for (c = exact; *c != 'e'; c++) {
        if (*c == '.')
            continue;
        if (k < p)
            head = head * 10 + (uint64_t)(*c - '0');
        else if (*c != (k == p ? '5' : '0'))
            return 0;
        k++;
    }
    return head == d;
}

/* The p-digit decimal d x 10^scale closest to the finite a > 0 that parses back to a, if there
 * is one (returns 1). */
static int digits_of_length(double a, int p, uint64_t *d, int *scale)
{
    char sci[48];
    const char *c;
    double rounded;
    /* The correctly rounded p-digit decimal (glibc's printf is exact): the closest. */
    snprintf(sci, sizeof sci, "%.*e", p - 1, a);
    *d = 0;
    for (c = sci; *c != 'e'; c++)
        if (*c != '.')
            *d = *d * 10 + (uint64_t)(*c - '0');
    *scale = atoi(c + 1) - (p - 1);
    rounded = strtod(sci, NULL);
    if (rounded == a) {
        /* printf breaks an exact tie to the even digit, Rust upwards: take the upper decimal
         * when a lies exactly halfway and it parses back to a too. */
        if (is_tie_below(a, p, *d)) {
            snprintf(sci, sizeof sci, "%llue%d", (unsigned long long)(*d + 1), *scale);
            if (strtod(sci, NULL) == a)
                ++*d;
        }
        return 1;
    }
    /* It does not parse back to a, but the p-digit decimal on the other side of a may: at a
     * power of two the interval that parses back to a is narrower below than above. */
    *d = rounded > a ? *d - 1 : *d + 1;
    snprintf(sci, sizeof sci, "%llue%d", (unsigned long long)*d, *scale);
    return strtod(sci, NULL) == a;
}

/* The shortest decimal digits of the finite a > 0 that parse back to a (the closest such, ties
 * upwards, as Rust's formatting): the digits d1 d2 ... dn in `digits`, and the exponent of d1
 * (a ~ d1.d2...dn x 10^exponent). */
static void shortest_digits(double a, char digits[24], int *exponent)
{
    /* Whether some p-digit decimal parses back to a grows with p (a p-digit decimal is also a
     * (p + 1)-digit one), and 17 digits always do: bisect for the least p. */
    int lo = 1, hi = 17, scale;
    uint64_t d;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (digits_of_length(a, mid, &d, &scale))
            hi = mid;
        else
            lo = mid + 1;
    }
    digits_of_length(a, lo, &d, &scale);
    while (d % 10 == 0) {
        d /= 10;
        scale++;
    }
    snprintf(digits, 24, "%llu", (unsigned long long)d);
    *exponent = scale + (int)strlen(digits) - 1;
}

/* Writes `v` as hyst-io writes it (crates/hyst-io/src/table.rs, push_f64: Rust's `{}` and
 * `{:e}`): the shortest digits that parse back to `v`, in plain notation when |v| is 0 or in
 * [1e-5, 1e16) (`-0`, `0.00001`, `1234.5`, `1000000000000000`), else as `1.5e-7`, `1e300`. */
static void format_shortest(double v, char *out, size_t size)
{
    char digits[24];
    int exponent, n, k;
    double a = fabs(v);
    const char *sign = signbit(v) ? "-" : "";
    size_t used;

    if (a == 0 || !isfinite(a)) { /* (non-finite values are never written) */
        snprintf(out, size, "%s%s", sign, a == 0 ? "0" : a == a ? "inf" : "NaN");
        return;
    }
    shortest_digits(a, digits, &exponent);
    n = (int)strlen(digits);
    if (!(a >= 1e-5 && a < 1e16)) {
        snprintf(out, size, "%s%c%s%se%d", sign, digits[0], n > 1 ? "." : "", digits + 1, exponent);
    } else if (exponent >= n - 1) { /* an integer: the digits, then zeros */
        used = (size_t)snprintf(out, size, "%s%s", sign, digits);
        for (k = 0; k < exponent - (n - 1) && used + 1 < size; k++)
            out[used++] = '0';
        out[used] = '\0';
    } else if (exponent >= 0) { /* d.ddd */
        snprintf(out, size, "%s%.*s.%s", sign, exponent + 1, digits, digits + exponent + 1);
    } else { /* 0.000ddd */
        used = (size_t)snprintf(out, size, "%s0.", sign);
        for (k = 0; k < -exponent - 1 && used + 1 < size; k++)
            out[used++] = '0';
        snprintf(out + used, size - used, "%s", digits);
    }
}

/* ------------------------------------------------------------------------------------------ */

int main(int argc, char **argv)
{
    const char *model_path = NULL, *column = NULL;
    int direct = 0, status = 1, i;
    char *text = NULL;
    size_t text_len = 0, j, header_line, columns = 0, rows = 0;
    char **names = NULL;
    long chosen = -1;
    reader rd;
    record rec = {NULL, 0, 0, 0};
    bytes cell = {NULL, 0, 0};
    doubles x = {NULL, 0, 0};
    sizes lines = {NULL, 0, 0}; /* the line of each sample */
    double *y = NULL;
    hyst_model *model = NULL;
    char error[1024];
    int got;

    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--column") == 0) {
            if (i + 1 == argc) {
                fail("--column needs a NAME");
                usage(stderr);
                return 2;
            }
            column = argv[++i];
        } else if (strcmp(argv[i], "--direct") == 0) {
            direct = 1;
        } else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            fail("unknown option %s", argv[i]);
            usage(stderr);
            return 2;
        } else if (!model_path) {
            model_path = argv[i];
        } else {
            fail("one model file only (got %s and %s)", model_path, argv[i]);
            usage(stderr);
            return 2;
        }
    }
    if (!model_path) {
        usage(stderr);
        return 2;
    }

    /* The model first: a bad model file is reported before the data is read. */
    model = hyst_model_load(model_path, error, sizeof error);
    if (!model) {
        size_t n = strlen(error);
        while (n > 0 && error[n - 1] == '\n') /* (a TOML error ends with a newline) */
            error[--n] = '\0';
        fail("%s", error);
        goto done;
    }

    text = read_all(stdin, &text_len);
    if (!text) {
        fail(SOURCE ": cannot read: %s", strerror(errno));
        goto done;
    }
    rd.text = text;
    rd.len = text_len;
    rd.pos = 0;
    rd.line = 1;
    if (text_len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0)
        rd.pos = 3;

    /* Header. */
    got = next_record(&rd, &rec, &cell);
    if (got < 0)
        goto out_of_memory;
    if (got == 0) {
        fail(SOURCE ": no header row: the input is empty (only blank lines and # comments)");
        goto done;
    }
    header_line = rec.line;
    columns = rec.count;
    names = (char **)calloc(columns, sizeof *names);
    if (!names)
        goto out_of_memory;
    {
        int all_numbers = 1;
        for (j = 0; j < columns; j++) {
            double ignored;
            names[j] = rec.cells[j];
            rec.cells[j] = NULL;
            if (parse_number(names[j], &ignored) < 0)
                all_numbers = 0;
        }
        rec.count = 0;
        if (all_numbers) {
            fail(SOURCE ":%zu: no header row: the first row contains only numbers; add a first "
                        "line with the column names, e.g. \"x,y\"",
                 header_line);
            goto done;
        }
    }
    for (j = 0; j < columns; j++) {
        size_t k;
        if (names[j][0] == '\0') {
            fail(SOURCE ":%zu: column %zu: empty column name in the header", header_line, j + 1);
            goto done;
        }
        for (k = 0; k < j; k++) {
            if (strcmp(names[k], names[j]) == 0) {
                fail(SOURCE ":%zu: column %zu (\"%s\"): duplicate column name (column %zu has the "
                            "same name)",
                     header_line, j + 1, names[j], k + 1);
                goto done;
            }
        }
    }
    /* The column: --column, else `x`, else the only one. Reported after the rows are checked,
     * as hyst reads the whole table first. */
    for (j = 0; j < columns; j++)
        if (strcmp(names[j], column ? column : "x") == 0)
            chosen = (long)j;
    if (chosen < 0 && !column && columns == 1)
        chosen = 0;

    /* Rows: every cell a finite number. */
    while ((got = next_record(&rd, &rec, &cell)) > 0) {
        rows++;
        if (rec.count != columns) {
            fail(SOURCE ":%zu: expected %zu cells (one per column of the header on line %zu), "
                        "found %zu",
                 rec.line, columns, header_line, rec.count);
            goto done;
        }
        for (j = 0; j < columns; j++) {
            double v = 0;
            int parsed = parse_number(rec.cells[j], &v);
            if (parsed < 0) {
                fail(SOURCE ":%zu: column %zu (\"%s\"): cannot parse \"%s\" as a number", rec.line,
                     j + 1, names[j], rec.cells[j]);
                goto done;
            }
            if (parsed > 0) {
                fail(SOURCE ":%zu: column %zu (\"%s\"): \"%s\" is not a finite number", rec.line,
                     j + 1, names[j], rec.cells[j]);
                goto done;
            }
            if ((long)j == chosen &&
                (doubles_push(&x, v) != 0 || sizes_push(&lines, rec.line) != 0))
                goto out_of_memory;
        }
    }
    if (got < 0)
        goto out_of_memory;
    if (rows == 0) {
        fail(SOURCE ": no data rows: the header is on line %zu and nothing follows it",
             header_line);
        goto done;
    }
    if (chosen < 0) {
        fprintf(stderr, "%s: " SOURCE ": ", program);
        if (column)
            fprintf(stderr, "no column \"%s\"", column);
        else
            fprintf(stderr, "which column? there is no column \"x\"; give --column NAME");
        fprintf(stderr, " (columns:");
        for (j = 0; j < columns; j++)
            fprintf(stderr, "%s \"%s\"", j ? "," : "", names[j]);
        fprintf(stderr, ")\n");
        goto done;
    }

    /* The model over the column, one record. One sample per call: a refused sample is then
     * named by its line (a call may take any block; later calls continue the record). */
    y = (double *)malloc(x.len * sizeof *y);
    if (!y)
        goto out_of_memory;
    for (j = 0; j < x.len; j++) {
        int s = hyst_model_process(model, direct ? 0 : 1, &x.data[j], &y[j], 1);
        if (s != HYST_OK) {
            char shown[40];
            format_shortest(x.data[j], shown, sizeof shown);
            fail(SOURCE ":%zu: column %ld (\"%s\"): value %s: the %s refuses it: %s (status %d)",
                 lines.data[j], chosen + 1, names[chosen], shown,
                 direct ? "model" : "inverse", hyst_status_message(s), s);
            goto done;
        }
        if (!isfinite(y[j])) { /* e.g. an output gain times 1e308: hyst run refuses it too */
            char shown[40];
            format_shortest(x.data[j], shown, sizeof shown);
            fail(SOURCE ":%zu: column %ld (\"%s\"): value %s: the %s's result is not finite",
                 lines.data[j], chosen + 1, names[chosen], shown,
                 direct ? "model" : "inverse");
            goto done;
        }
    }

    /* Output. */
    {
        char a[40], b[40];
        fputs("x,y\n", stdout);
        for (j = 0; j < x.len; j++) {
            format_shortest(x.data[j], a, sizeof a);
            format_shortest(y[j], b, sizeof b);
            fprintf(stdout, "%s,%s\n", a, b);
        }
        if (fflush(stdout) != 0 || ferror(stdout)) {
            fail("cannot write the output: %s", strerror(errno));
            goto done;
        }
    }
    status = 0;
    goto done;

out_of_memory:
    fail("out of memory");
done:
    hyst_model_free(model);
    free(y);
    free(x.data);
    free(lines.data);
    record_free(&rec);
    free(cell.data);
    if (names) {
        for (j = 0; j < columns; j++)
            free(names[j]);
        free(names);
    }
    free(text);
    return status;
}
