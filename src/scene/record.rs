//! Rewriting a scene file's `expect` field in place (`nearmiss test
//! --record`), keeping everything else of the text, comments included.
//!
//! A small scanner walks the RON text, skipping strings and comments and
//! tracking bracket depth, to find the scene's top-level `expect:` value;
//! it is replaced, or a new field is added before the scene's closing
//! parenthesis.

/// The comment put above a recorded expectation.
pub const RECORDED_COMMENT: &str =
    "// expect: recorded by `nearmiss test --record` from a run, not derived by analysis";

/// `text` with its top-level `expect` field set to `value` (RON), marked
/// by [`RECORDED_COMMENT`]; an error if the text's structure is not a
/// `Scene(...)` the scanner can follow.
pub fn set_expectation(text: &str, value: &str) -> Result<String, String> {
    let bytes = text.as_bytes();
    let mut depth = 0usize;
    let mut i = 0;
    let (mut expect, mut close) = (None::<(usize, usize)>, None::<usize>);
    // The start of the `expect` value, while it is being scanned.
    let mut value_start = None::<usize>;
    while i < bytes.len() {
        match bytes[i] {
            b'"' => {
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i + 1 < bytes.len() && !(bytes[i] == b'*' && bytes[i + 1] == b'/') {
                    i += 1;
                }
                i += 1;
            }
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => {
                if depth == 1 {
                    if let Some(start) = value_start.take() {
                        expect = Some((start, i));
                    }
                    close = Some(i);
                    break;
                }
                depth = depth.saturating_sub(1);
            }
            b',' if depth == 1 => {
                if let Some(start) = value_start.take() {
                    expect = Some((start, i));
                }
            }
            b'e' if depth == 1
                && value_start.is_none()
                && expect.is_none()
                && text[i..].starts_with("expect") =>
            {
                let before = i.checked_sub(1).map(|k| bytes[k]);
                let after = text[i + "expect".len()..].trim_start();
                if !before.is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_') && after.starts_with(':') {
                    let colon = text.len() - after.len();
                    value_start = Some(colon + 1);
                    i = colon;
                }
            }
            _ => {}
        }
        i += 1;
    }
    let close = close.ok_or("no closing parenthesis of `Scene(...)` found")?;
    match expect {
        Some((start, end)) => {
            // Mark it, unless the line above already carries the mark.
            let field = text[..start].rfind("expect").unwrap_or(start);
            let line_start = text[..field].rfind('\n').map_or(0, |k| k + 1);
            let indent = &text[line_start..field];
            let marked = text[..line_start].trim_end().ends_with(RECORDED_COMMENT);
            let mark = if marked || !indent.trim().is_empty() {
                String::new()
            } else {
                format!("{indent}{RECORDED_COMMENT}\n")
            };
            Ok(format!("{}{mark}{} {value}{}", &text[..line_start], &text[line_start..start], &text[end..]))
        }
        None => {
            let head = text[..close].trim_end();
            let comma = if head.ends_with(',') || head.ends_with('(') { "" } else { "," };
            Ok(format!("{head}{comma}\n    {RECORDED_COMMENT}\n    expect: {value},\n{}", &text[close..]))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_expect_field_is_replaced_and_comments_and_strings_are_left_alone() {
        let text = "// expect: in a comment\nScene(\n    name: \"expect: x\",\n    dt: 0.1,\n    expect: NoContact,\n    steps: 1,\n)";
        let out = set_expectation(
            text,
            "Contact(time: 1.0, tolerance: 0.1, bodies: (\"a\", \"b\"), recorded: true)",
        )
        .unwrap();
        assert!(out.starts_with("// expect: in a comment\nScene(\n    name: \"expect: x\",\n    dt: 0.1,\n"));
        assert!(out.contains(&format!("    {RECORDED_COMMENT}\n    expect: Contact(time: 1.0")));
        assert!(out.ends_with("recorded: true),\n    steps: 1,\n)"));
        // Recording again replaces the value and keeps one mark.
        let again = set_expectation(&out, "NoContact").unwrap();
        assert_eq!(again.matches(RECORDED_COMMENT).count(), 1);
        assert!(again.contains("    expect: NoContact,\n    steps: 1"));
    }

    #[test]
    fn look_alike_names_and_an_unnamed_struct_are_handled() {
        // `expected_speed` is not `expect`; the struct name may be omitted.
        let text = "(expected_speed: 1.0, name: \"s\", expect: NoContact)";
        let out = set_expectation(text, "NoContact").unwrap();
        assert!(out.starts_with("(expected_speed: 1.0, name: \"s\", expect: NoContact)"), "{out}");
        let text = "(expected_speed: 1.0)";
        assert!(set_expectation(text, "NoContact").unwrap().contains("expected_speed: 1.0,\n"));
    }

    #[test]
    fn a_missing_expect_field_is_added_before_the_closing_parenthesis() {
        let out =
            set_expectation("Scene(name: \"s\", dt: 0.1, steps: 1, bodies: [(name: \"a\")])", "NoContact")
                .unwrap();
        assert!(out.ends_with(&format!(
            "bodies: [(name: \"a\")],\n    {RECORDED_COMMENT}\n    expect: NoContact,\n)"
        )));
        assert!(set_expectation("Scene(name: \"s\"", "NoContact").is_err());
    }
}
