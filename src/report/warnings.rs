//! Warnings as a person reads them: many of one kind (2,000 small
//! obstacles each covering no wind cell) are one line with a count, not
//! 2,000 lines. The reports keep every one.

/// `text` with every number masked: warnings that differ only in an
/// index, a position or a size are of one kind.
fn kind(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut in_number = false;
    for c in text.chars() {
        let numeric = c.is_ascii_digit() || (in_number && (c == '.' || c == 'e'));
        if numeric {
            if !in_number {
                out.push('#');
            }
        } else {
            out.push(c);
        }
        in_number = numeric;
    }
    out
}

/// The warnings to print: the first of each kind, in order, with how many
/// more of its kind followed.
pub fn collapsed(warnings: &[String]) -> Vec<String> {
    let mut kinds: Vec<(String, &String, usize)> = Vec::new();
    for w in warnings {
        let k = kind(w);
        match kinds.iter_mut().find(|(seen, _, _)| *seen == k) {
            Some((_, _, more)) => *more += 1,
            None => kinds.push((k, w, 0)),
        }
    }
    kinds
        .into_iter()
        .map(|(_, first, more)| match more {
            0 => first.clone(),
            n => format!("{first} (and {n} more like it; the report lists each)"),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warnings_of_one_kind_are_one_line_with_a_count() {
        let mut warnings: Vec<String> = (0..2000)
            .map(|i| format!("wind obstacle {i} covers no cell of the wind domain [-1.5, 0, -2]..[1.5, 2, 2]; it blocks no air"))
            .collect();
        warnings.insert(
            1,
            "wind source at [9, 1, 0] lies outside the wind domain".into(),
        );
        let lines = collapsed(&warnings);
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert!(lines[0].starts_with("wind obstacle 0 covers no cell"));
        assert!(lines[0].ends_with("(and 1999 more like it; the report lists each)"));
        assert_eq!(lines[1], warnings[1]);
        // Different words: different kinds.
        let two = collapsed(&["a 1".into(), "b 1".into()]);
        assert_eq!(two, ["a 1", "b 1"]);
    }
}
