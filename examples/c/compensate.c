/*
 * compensate: a host program in C99 over the hyst C API (include/hyst.h).
 *
 *   compensate MODEL.toml [--column NAME] [--direct] < in.csv > out.csv
 *
 * Reads a CSV table with a header row on stdin, runs the fitted model's exact inverse (desired
 * output in, command out: the feed-forward compensation of the modelled hysteresis; with
 * --direct the model itself: input in, output out) over one column as one record, and writes to
 * stdout every column of the input, each cell as read (trimmed; text too), then the result,
 * named after what it is: the model's input column (the command, e.g. `u_actuator_V`), its
 * output column with --direct (e.g. `y_capsensor_um`); a name the input already has gets `_out`
 * appended (until it is new). The output is byte for byte that of
 *
 *   hyst run --model MODEL.toml [--inverse] --column NAME in.csv -o out.csv
 *
 * Column: --column NAME, else the model's output column (its input column with --direct), as
 * `hyst run --model` takes it; when the table has no such column, `x`, else the only column.
 * The model file's column names come from hyst_model_column().
 *
 * The CSV is read as hyst-io reads it: blank lines and lines starting with `#` are skipped but
 * counted, cells are trimmed of whitespace (Unicode's, as Rust's str::trim), `"quoted"` cells,
 * CRLF and a UTF-8 BOM are accepted, every row has one cell per column and every cell is UTF-8.
 * Only the chosen column must hold finite numbers; the other columns may hold text.
 *
 * Cells are written back as hyst-io writes them (push_cell): quoted when empty, holding `,`,
 * `"`, CR or LF, with surrounding whitespace, or a row's first cell starting with `#` (`"`
 * doubled inside). Numbers are written as hyst-io writes them: the shortest decimal that parses
 * back to the identical double (so the text round-trips exactly, like %.17g, but is also
 * identical to the CLI's), in plain notation for magnitudes in [1e-5, 1e16) and as `1.5e-7`
 * otherwise.
 *
 * Errors go to stderr, naming the line and column (`<stdin>:LINE: column C ("name"): ...`),
 * with exit status 1 (2 for a usage error); nothing is written to stdout then. As `hyst run`,
 * the error is the first, in file order, of a row that cannot be read and a sample the model
 * refuses.
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
            "  model itself) over the column NAME (default: the model's output column, its\n"
            "  input column with --direct; else `x`, else the only column) and writes every\n"
            "  input column, then the result named after the model's input column (its output\n"
            "  column with --direct; `_out` appended if the input has that name)\n",
            program);
}

/* ------------------------------------------------------------------------------------------ */
/* Growing buffers. */

typedef struct {
    char *data;
    size_t len, cap;
} bytes;

/* Appends the n bytes at `data`; -1 when out of memory. */
static int bytes_append(bytes *b, const char *data, size_t n)
{
    if (b->cap - b->len < n) {
        size_t cap = b->cap ? b->cap : 256;
        char *grown;
        while (cap - b->len < n) {
            if (cap > (size_t)-1 / 2)
                return -1;
            cap *= 2;
        }
        grown = (char *)realloc(b->data, cap);
        if (!grown)
            return -1;
        b->data = grown;
        b->cap = cap;
    }
    if (n > 0)
        memcpy(b->data + b->len, data, n);
    b->len += n;
    return 0;
}

static int bytes_push(bytes *b, char c)
{
    return bytes_append(b, &c, 1);
}

/* Reads the whole stream (NUL-terminated, the length without the NUL in *len). */
static char *read_all(FILE *f, size_t *len)
{
    bytes b = {NULL, 0, 0};
    char chunk[65536];
    size_t got;
    while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) {
        if (bytes_append(&b, chunk, got) != 0) {
            free(b.data);
            return NULL;
        }
    }
    if (ferror(f) || bytes_push(&b, '\0') != 0) {
        free(b.data);
        return NULL;
    }
    *len = b.len - 1;
    return b.data;
}

/* ------------------------------------------------------------------------------------------ */
/* Text as Rust's str sees it: UTF-8, and whitespace (char::is_whitespace, Unicode's
 * White_Space), which str::trim removes. A cell is held with its length: it may hold a NUL. */

typedef struct {
    char *data; /* NUL-terminated too */
    size_t len;
} text;

/* The length of the whitespace character at the start of the n bytes at s, or 0: U+0009 to
 * U+000D, U+0020, U+0085, U+00A0, U+1680, U+2000 to U+200A, U+2028, U+2029, U+202F, U+205F,
 * U+3000. */
static size_t space_at(const char *at, size_t n)
{
    const unsigned char *s = (const unsigned char *)at;
    if (n >= 1 && ((s[0] >= 0x09 && s[0] <= 0x0D) || s[0] == 0x20))
        return 1;
    if (n >= 2 && s[0] == 0xC2 && (s[1] == 0x85 || s[1] == 0xA0))
        return 2;
    if (n >= 3 && ((s[0] == 0xE1 && s[1] == 0x9A && s[2] == 0x80) ||
                   (s[0] == 0xE2 && s[1] == 0x80 &&
                    ((s[2] >= 0x80 && s[2] <= 0x8A) || s[2] == 0xA8 || s[2] == 0xA9 ||
                     s[2] == 0xAF)) ||
                   (s[0] == 0xE2 && s[1] == 0x81 && s[2] == 0x9F) ||
                   (s[0] == 0xE3 && s[1] == 0x80 && s[2] == 0x80)))
        return 3;
    return 0;
}

/* The length of the whitespace character that ends the `end` bytes at s, or 0. */
static size_t space_before(const char *s, size_t end)
{
    size_t k;
    for (k = 1; k <= 3 && k <= end; k++)
        if (space_at(s + end - k, k) == k)
            return k;
    return 0;
}

/* The bounds [*start, *end) of the n bytes at s without surrounding whitespace. */
static void trim(const char *s, size_t n, size_t *start, size_t *end)
{
    size_t a = 0, b = n, k;
    while (a < b && (k = space_at(s + a, b - a)) > 0)
        a += k;
    while (b > a && (k = space_before(s, b)) > 0 && b - k >= a)
        b -= k;
    *start = a;
    *end = b;
}

/* Whether the n bytes at s are UTF-8 as Rust's str::from_utf8 accepts it (no overlong forms,
 * no surrogates, nothing beyond U+10FFFF). */
static int is_utf8(const char *at, size_t n)
{
    const unsigned char *s = (const unsigned char *)at;
    size_t i = 0, k, j;
    while (i < n) {
        unsigned long c = s[i], least;
        if (c < 0x80) {
            i++;
            continue;
        }
        if (c >= 0xC2 && c <= 0xDF) {
            k = 1;
            c &= 0x1F;
            least = 0x80;
        } else if (c >= 0xE0 && c <= 0xEF) {
            k = 2;
            c &= 0x0F;
            least = 0x800;
        } else if (c >= 0xF0 && c <= 0xF4) {
            k = 3;
            c &= 0x07;
            least = 0x10000;
        } else {
            return 0;
        }
        if (n - i - 1 < k)
            return 0;
        for (j = 1; j <= k; j++) {
            if ((s[i + j] & 0xC0) != 0x80)
                return 0;
            c = (c << 6) | (s[i + j] & 0x3F);
        }
        if (c < least || c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF))
            return 0;
        i += k + 1;
    }
    return 1;
}

/* Whether the text holds one of the bytes of `set`. */
static int holds_any(const text *t, const char *set)
{
    size_t i;
    for (i = 0; i < t->len; i++)
        if (t->data[i] != '\0' && strchr(set, t->data[i]))
            return 1;
    return 0;
}

static int text_is(const text *t, const char *s)
{
    return t->len == strlen(s) && memcmp(t->data, s, t->len) == 0;
}

static int text_equal(const text *a, const text *b)
{
    return a->len == b->len && memcmp(a->data, b->data, a->len) == 0;
}

/* Appends `t` quoted (`"` doubled inside) when `quote`, else as it is; -1 when out of memory. */
static int append_text(bytes *out, const text *t, int quote)
{
    size_t i;
    if (!quote)
        return bytes_append(out, t->data, t->len);
    if (bytes_push(out, '"') != 0)
        return -1;
    for (i = 0; i < t->len; i++)
        if ((t->data[i] == '"' && bytes_push(out, '"') != 0) || bytes_push(out, t->data[i]) != 0)
            return -1;
    return bytes_push(out, '"');
}

/* Appends a data cell as hyst-io's push_cell writes it: quoted when it would not read back as
 * itself (empty, a separator, a quote or a line break in it, surrounding whitespace, or a `#`
 * starting the line). */
static int append_cell(bytes *out, const text *cell, int first)
{
    size_t start, end;
    trim(cell->data, cell->len, &start, &end);
    return append_text(out, cell,
                       cell->len == 0 || holds_any(cell, ",\"\n\r") || start > 0 ||
                           end < cell->len || (first && cell->data[0] == '#'));
}

/* Appends a column name as hyst-io's write_header writes it: quoted when it holds `,`, `"` or a
 * line break, or is the first and starts with `#`. */
static int append_name(bytes *out, const text *name, int first)
{
    return append_text(out, name,
                       holds_any(name, ",\"\n\r") ||
                           (first && name->len > 0 && name->data[0] == '#'));
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
    text *cells; /* each trimmed */
    size_t count, cap;
    size_t line; /* the line of the record's first byte */
} record;

static void record_clear(record *r)
{
    size_t i;
    for (i = 0; i < r->count; i++)
        free(r->cells[i].data);
    r->count = 0;
}

static void record_free(record *r)
{
    record_clear(r);
    free(r->cells);
    r->cells = NULL;
    r->cap = 0;
}

/* Appends the cell in `b` (trimmed) to `r`; -1 when out of memory. */
static int record_push(record *r, bytes *b)
{
    size_t start, end;
    char *cell;
    trim(b->data, b->len, &start, &end);
    if (r->count == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 8;
        text *cells = (text *)realloc(r->cells, cap * sizeof *cells);
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
    r->cells[r->count].data = cell;
    r->cells[r->count].len = end - start;
    r->count++;
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
        /* A line of whitespace only (one cell, empty once trimmed) is skipped too. */
        if (!(r->count == 1 && r->cells[0].len == 0))
            return 1;
    }
}

/* ------------------------------------------------------------------------------------------ */
/* Numbers. */

/* Parses a cell as Rust's f64::from_str does: [+-] then digits with an optional `.` (at least
 * one digit) and an optional exponent, or inf / infinity / nan. Returns 0 with a finite value,
 * 1 for a number that is not finite (nan, inf, 1e999), -1 for text that is not a number. */
static int parse_number(const text *cell, double *value)
{
    const char *s = cell->data, *p = s, *word;
    size_t digits = 0;
    char *end;
    if (strlen(s) != cell->len) /* a NUL byte in it */
        return -1;
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
/* The model's column names. */

/* The model file's column `which` (HYST_COLUMN_INPUT or HYST_COLUMN_OUTPUT), allocated (free
 * it); NULL after saying why. */
static char *model_column(const hyst_model *model, int32_t which)
{
    const char *what = which == HYST_COLUMN_INPUT ? "input" : "output";
    size_t needed = 0;
    char *name;
    int32_t s = hyst_model_column(model, which, NULL, 0, &needed); /* its size */
    if (s != HYST_ERR_LENGTH) {
        fail("the model's %s column name: %s (status %d)", what, hyst_status_message(s), s);
        return NULL;
    }
    name = (char *)malloc(needed);
    if (!name) {
        fail("out of memory");
        return NULL;
    }
    s = hyst_model_column(model, which, name, needed, NULL);
    if (s != HYST_OK) {
        fail("the model's %s column name: %s (status %d)", what, hyst_status_message(s), s);
        free(name);
        return NULL;
    }
    return name;
}

/* The name of the computed column: `base` with `_out` appended until no input column has it
 * (`names`, `columns` of them). Allocated (free it); NULL when out of memory. */
static char *computed_name(const char *base, const text *names, size_t columns)
{
    size_t len = strlen(base), j;
    char *name = (char *)malloc(len + 1);
    if (!name)
        return NULL;
    memcpy(name, base, len + 1);
    for (;;) {
        text t;
        char *longer;
        t.data = name;
        t.len = len;
        for (j = 0; j < columns && !text_equal(&names[j], &t); j++)
            ;
        if (j == columns)
            return name;
        longer = (char *)realloc(name, len + 5);
        if (!longer) {
            free(name);
            return NULL;
        }
        name = longer;
        memcpy(name + len, "_out", 5);
        len += 4;
    }
}

/* ------------------------------------------------------------------------------------------ */

int main(int argc, char **argv)
{
    const char *model_path = NULL, *column = NULL;
    int direct = 0, status = 1, i;
    char *text_in = NULL, *model_in = NULL, *model_out = NULL, *result = NULL;
    size_t text_len = 0, j, header_line, columns = 0, rows = 0, chosen = (size_t)-1;
    text *names = NULL;
    reader rd;
    record rec = {NULL, 0, 0, 0};
    bytes cell = {NULL, 0, 0}, out = {NULL, 0, 0};
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
    /* Its column names: the default input column and the name of the result. */
    model_in = model_column(model, HYST_COLUMN_INPUT);
    model_out = model_in ? model_column(model, HYST_COLUMN_OUTPUT) : NULL;
    if (!model_out)
        goto done;

    text_in = read_all(stdin, &text_len);
    if (!text_in) {
        fail(SOURCE ": cannot read: %s", strerror(errno));
        goto done;
    }
    rd.text = text_in;
    rd.len = text_len;
    rd.pos = 0;
    rd.line = 1;
    if (text_len >= 3 && memcmp(text_in, "\xEF\xBB\xBF", 3) == 0)
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
    names = (text *)calloc(columns, sizeof *names);
    if (!names)
        goto out_of_memory;
    for (j = 0; j < columns; j++) {
        names[j] = rec.cells[j];
        rec.cells[j].data = NULL;
        if (!is_utf8(names[j].data, names[j].len)) {
            fail(SOURCE ":%zu: column %zu: invalid UTF-8 in the header", header_line, j + 1);
            goto done;
        }
    }
    rec.count = 0;
    {
        /* The first name also loses BOMs (U+FEFF) among its leading whitespace, as hyst-io's. */
        size_t start = 0, k, end;
        for (;;) {
            if (names[0].len - start >= 3 && memcmp(names[0].data + start, "\xEF\xBB\xBF", 3) == 0)
                start += 3;
            else if ((k = space_at(names[0].data + start, names[0].len - start)) > 0)
                start += k;
            else
                break;
        }
        trim(names[0].data + start, names[0].len - start, &k, &end);
        memmove(names[0].data, names[0].data + start + k, end - k);
        names[0].len = end - k;
        names[0].data[names[0].len] = '\0';
    }
    {
        int all_numbers = 1;
        for (j = 0; j < columns; j++) {
            double ignored;
            if (parse_number(&names[j], &ignored) < 0)
                all_numbers = 0;
        }
        if (all_numbers) {
            fail(SOURCE ":%zu: no header row: the first row contains only numbers; add a first "
                        "line with the column names, e.g. \"x,y\"",
                 header_line);
            goto done;
        }
    }
    for (j = 0; j < columns; j++) {
        size_t k;
        if (names[j].len == 0) {
            fail(SOURCE ":%zu: column %zu: empty column name in the header", header_line, j + 1);
            goto done;
        }
        for (k = 0; k < j; k++) {
            if (text_equal(&names[k], &names[j])) {
                fail(SOURCE ":%zu: column %zu (\"%s\"): duplicate column name (column %zu has the "
                            "same name)",
                     header_line, j + 1, names[j].data, k + 1);
                goto done;
            }
        }
    }

    /* The column: --column, else the model's (as hyst run --model), else `x`, else the only
     * one; chosen before the rows are read, as hyst run does. */
    {
        const char *wanted = column ? column : direct ? model_in : model_out;
        for (j = 0; j < columns && chosen == (size_t)-1; j++)
            if (text_is(&names[j], wanted))
                chosen = j;
        for (j = 0; j < columns && chosen == (size_t)-1 && !column; j++)
            if (text_is(&names[j], "x"))
                chosen = j;
        if (chosen == (size_t)-1 && !column && columns == 1)
            chosen = 0;
        if (chosen == (size_t)-1) {
            fprintf(stderr, "%s: " SOURCE ": ", program);
            if (column)
                fprintf(stderr, "no column \"%s\"", column);
            else
                fprintf(stderr,
                        "which column? there is no column \"%s\" (the model's %s column) nor "
                        "\"x\"; give --column NAME",
                        wanted, direct ? "input" : "output");
            fprintf(stderr, " (columns:");
            for (j = 0; j < columns; j++)
                fprintf(stderr, "%s \"%s\"", j ? "," : "", names[j].data);
            fprintf(stderr, ")\n");
            goto done;
        }
    }

    /* The output's header: every input column, then the result, named after what it is (the
     * model's input column for the inverse, its output column for the model itself). */
    for (j = 0; j < columns; j++) {
        if (holds_any(&names[j], "\n\r")) { /* (hyst run cannot write it back either) */
            fail(SOURCE ":%zu: column %zu (\"%s\"): a column name with a line break cannot head "
                        "the output",
                 header_line, j + 1, names[j].data);
            goto done;
        }
    }
    result = computed_name(direct ? model_out : model_in, names, columns);
    if (!result)
        goto out_of_memory;
    {
        text r;
        size_t start, end;
        r.data = result;
        r.len = strlen(result);
        trim(r.data, r.len, &start, &end);
        if (start == end || start > 0 || end < r.len || holds_any(&r, "\n\r")) {
            /* (hyst run refuses such a name too: it would not read back as itself) */
            fail("the model's %s column name \"%s\" cannot name a CSV column: %s",
                 direct ? "output" : "input", result,
                 start == end ? "it is empty"
                              : holds_any(&r, "\n\r") ? "it holds a line break"
                                                      : "it has leading or trailing whitespace");
            goto done;
        }
        for (j = 0; j < columns; j++)
            if (append_name(&out, &names[j], j == 0) != 0 || bytes_push(&out, ',') != 0)
                goto out_of_memory;
        if (append_name(&out, &r, 0) != 0 || bytes_push(&out, '\n') != 0)
            goto out_of_memory;
    }

    /* Rows, one at a time as hyst run streams them: the chosen cell a finite number, every cell
     * UTF-8, then the sample through the model (one record: later calls continue it), so the
     * first row that fails, in file order, is the one named. */
    while ((got = next_record(&rd, &rec, &cell)) > 0) {
        const text *x_cell;
        double x = 0, y = 0;
        int parsed, s;
        char shown[40];
        rows++;
        if (rec.count != columns) {
            fail(SOURCE ":%zu: expected %zu cells (one per column of the header on line %zu), "
                        "found %zu",
                 rec.line, columns, header_line, rec.count);
            goto done;
        }
        x_cell = &rec.cells[chosen];
        if (!is_utf8(x_cell->data, x_cell->len)) {
            fail(SOURCE ":%zu: column %zu (\"%s\"): invalid UTF-8", rec.line, chosen + 1,
                 names[chosen].data);
            goto done;
        }
        parsed = parse_number(x_cell, &x);
        if (parsed < 0) {
            fail(SOURCE ":%zu: column %zu (\"%s\"): cannot parse \"%s\" as a number", rec.line,
                 chosen + 1, names[chosen].data, x_cell->data);
            goto done;
        }
        if (parsed > 0) {
            fail(SOURCE ":%zu: column %zu (\"%s\"): \"%s\" is not a finite number", rec.line,
                 chosen + 1, names[chosen].data, x_cell->data);
            goto done;
        }
        /* The other cells are passed through: any text, but UTF-8. */
        for (j = 0; j < columns; j++) {
            if (!is_utf8(rec.cells[j].data, rec.cells[j].len)) {
                fail(SOURCE ":%zu: column %zu (\"%s\"): invalid UTF-8", rec.line, j + 1,
                     names[j].data);
                goto done;
            }
        }
        s = hyst_model_process(model, direct ? 0 : 1, &x, &y, 1);
        if (s != HYST_OK) {
            format_shortest(x, shown, sizeof shown);
            fail(SOURCE ":%zu: column %zu (\"%s\"): value %s: the %s refuses it: %s (status %d)",
                 rec.line, chosen + 1, names[chosen].data, shown, direct ? "model" : "inverse",
                 hyst_status_message(s), s);
            goto done;
        }
        if (!isfinite(y)) { /* e.g. an output gain times 1e308: hyst run refuses it too */
            format_shortest(x, shown, sizeof shown);
            fail(SOURCE ":%zu: column %zu (\"%s\"): value %s: the %s's result is not finite",
                 rec.line, chosen + 1, names[chosen].data, shown, direct ? "model" : "inverse");
            goto done;
        }
        /* Every cell as read, then the result. */
        for (j = 0; j < columns; j++)
            if (append_cell(&out, &rec.cells[j], j == 0) != 0 || bytes_push(&out, ',') != 0)
                goto out_of_memory;
        format_shortest(y, shown, sizeof shown);
        if (bytes_append(&out, shown, strlen(shown)) != 0 || bytes_push(&out, '\n') != 0)
            goto out_of_memory;
    }
    if (got < 0)
        goto out_of_memory;
    if (rows == 0) {
        fail(SOURCE ": no data rows: the header is on line %zu and nothing follows it",
             header_line);
        goto done;
    }

    /* Output, all at once: nothing reaches stdout when anything failed. */
    if (fwrite(out.data, 1, out.len, stdout) != out.len || fflush(stdout) != 0 ||
        ferror(stdout)) {
        fail("cannot write the output: %s", strerror(errno));
        goto done;
    }
    status = 0;
    goto done;

out_of_memory:
    fail("out of memory");
done:
    hyst_model_free(model);
    free(model_in);
    free(model_out);
    free(result);
    record_free(&rec);
    free(cell.data);
    free(out.data);
    if (names) {
        for (j = 0; j < columns; j++)
            free(names[j].data);
        free(names);
    }
    free(text_in);
    return status;
}
