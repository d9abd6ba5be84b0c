//! Doc-comment text for the Rust that codegen writes (the kernels' module
//! and the ABI module): rustdoc reads `[x]` as an intra-doc link and `<t>`
//! as an HTML tag, so text written for every backend is escaped here once.

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

#[cfg(test)]
mod tests {
    use super::doc_text;

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
