//! Doc text written for every backend, as Markdown: the doc comments of
//! the Rust that codegen writes (the kernels' module and the ABI module)
//! and the cells of `generated/README.md`'s tables. Both readers (rustdoc,
//! a Markdown renderer) take `[x]` for a link and `<t>` for an HTML tag, so
//! the text is escaped here once.

/// Doc text (a scheme's, a function's, a constant's, an ABI field's) as
/// the body of a Rust `///` comment that rustdoc reads as plain text: `[`,
/// `]` and `<` outside `code spans` are backslash-escaped, so an index
/// like `displace_info[0]` or a type like `mat4x4<f32>` is not taken for
/// an intra-doc link or an HTML tag. The shader printers keep the text
/// as written.
pub(crate) fn doc_text(doc: &str) -> String {
    // Backticks pair up in order; an unpaired last one is literal text.
    let ticks = doc.matches('`').count();
    let mut seen = 0;
    let mut out = String::with_capacity(doc.len());
    for c in doc.chars() {
        let in_code = seen % 2 == 1 && seen <= ticks - ticks % 2;
        match c {
            '`' => seen += 1,
            '[' | ']' | '<' if !in_code => out.push('\\'),
            _ => {}
        }
        out.push(c);
    }
    out
}

/// [`doc_text`] as the text of a Markdown table cell, where `|` (even in
/// a code span) would end the cell.
pub(crate) fn table_cell(doc: &str) -> String {
    doc_text(doc).replace('|', "\\|")
}

#[cfg(test)]
mod tests {
    use super::{doc_text, table_cell};

    #[test]
    fn table_cell_escapes_the_cell_separator() {
        assert_eq!(table_cell("a | `b|c` <d>"), "a \\| `b\\|c` \\<d>");
    }

    #[test]
    fn doc_text_escapes_brackets_and_tags_outside_code_spans() {
        assert_eq!(
            doc_text("displace_info[0] == 0, `a[i]` and mat4x4<f32>"),
            "displace_info\\[0\\] == 0, `a[i]` and mat4x4\\<f32>"
        );
        // An unpaired backtick is text: what follows it is still escaped.
        assert_eq!(doc_text("`x` then ` b[1]"), "`x` then ` b\\[1\\]");
        assert_eq!(doc_text("no markup"), "no markup");
    }
}
