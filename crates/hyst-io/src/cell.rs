//! One text cell of a CSV line as hyst writes it: quoted where it would not read back as
//! itself. Shared by the table's writing of text columns and the reader's pass-through of a row
//! ([`CsvReader::push_cells`](crate::CsvReader::push_cells)).

/// Appends a text cell to a CSV line, quoted when it would not read back as itself (a separator,
/// a quote or a line break in it, surrounding whitespace, empty, or a `#` starting the line).
pub(crate) fn push_cell(line: &mut String, cell: &str, first: bool) {
    let needs_quotes = cell.is_empty()
        || cell.contains([',', '"', '\n', '\r'])
        || cell.trim() != cell
        || (first && cell.starts_with('#'));
    if needs_quotes {
        line.push('"');
        line.push_str(&cell.replace('"', "\"\""));
        line.push('"');
    } else {
        line.push_str(cell);
    }
}
