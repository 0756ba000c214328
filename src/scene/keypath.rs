//! Maps a byte offset of a TOML document (the span of a parse error) to the dotted key path that
//! holds it (`study[1].stretch.step`), so that messages name the key, not only a line.

/// The key path at `offset` in `text`, as well as it can be reconstructed from the text: table
/// headers (`[a.b]`, `[[study]]` counted as `study[i]`), the key of the line (or of the
/// multi-line array it continues) and the innermost key of an inline table.
pub fn key_path(text: &str, offset: usize) -> String {
    let offset = offset.min(text.len());
    let mut header = String::new();
    let mut counts: Vec<(String, usize)> = Vec::new();
    let mut line_start = 0;
    let mut last_key_line: Option<(usize, &str)> = None;
    for line in text.split_inclusive('\n') {
        let end = line_start + line.len();
        let body = strip_comment(line).trim();
        if line_start > offset {
            break;
        }
        if let Some(name) = body.strip_prefix("[[").and_then(|s| s.split("]]").next()) {
            // `[[study.regions]]` after the i-th `[[study]]` is an element of study[i].regions.
            let name = nested(name.trim(), &counts);
            let i = match counts.iter_mut().find(|(n, _)| *n == name) {
                Some((_, c)) => {
                    *c += 1;
                    *c - 1
                }
                None => {
                    counts.push((name.clone(), 1));
                    0
                }
            };
            header = format!("{name}[{i}]");
            last_key_line = None;
        } else if let Some(name) = body.strip_prefix('[').and_then(|s| s.split(']').next()) {
            // `[study.points]` after the i-th `[[study]]` is a table of that element: study[i].points.
            header = nested(name.trim(), &counts);
            last_key_line = None;
        } else if body.contains('=') && !starts_inside_value(body) {
            last_key_line = Some((line_start, line));
        }
        if offset < end || end == text.len() {
            break;
        }
        line_start = end;
    }
    let mut path = header;
    if let Some((start, line)) = last_key_line {
        let top = line
            .split('=')
            .next()
            .unwrap_or("")
            .trim()
            .trim_matches('"');
        push(&mut path, top);
        let within = offset.saturating_sub(start).min(line.len());
        if let Some(inner) = inline_key(line, within) {
            push(&mut path, &inner);
        }
    }
    if path.is_empty() {
        "(top level)".to_string()
    } else {
        path
    }
}

/// `first.rest` of a table header, with `first` an array of tables already counted in `counts`
/// (its i-th element open): `study[i].rest`; else `name` as it is.
fn nested(name: &str, counts: &[(String, usize)]) -> String {
    name.split_once('.')
        .and_then(|(first, rest)| {
            let (_, c) = counts.iter().find(|(n, _)| n == first.trim())?;
            Some(format!("{}[{}].{}", first.trim(), c - 1, rest.trim()))
        })
        .unwrap_or_else(|| name.to_string())
}

/// The innermost key of an inline table in `line` at byte `within`: the key at the offset, or
/// the last `key =` before it; `None` outside an inline table.
fn inline_key(line: &str, within: usize) -> Option<String> {
    let prefix = line.get(..within).unwrap_or("");
    let brace = prefix.find('{')?;
    let rest = line.get(within..).unwrap_or("");
    let word: String = rest
        .chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == '-')
        .collect();
    let after = rest.get(word.len()..).unwrap_or("").trim_start();
    if !word.is_empty() && after.starts_with('=') {
        return Some(word);
    }
    prefix
        .get(brace + 1..)
        .and_then(|s| s.rsplit(',').next())
        .and_then(|s| s.split('=').next())
        .map(str::trim)
        .filter(|s| !s.is_empty() && !s.contains(' '))
        .map(String::from)
}

/// The line (1-based) of `text` that writes `key` (`study[1].damage[2]`), or else the nearest
/// enclosing key or table that the text writes (`study[1].damage`, then `study[1]`): the reverse
/// of [`key_path`], for the errors that validation finds after parsing. `None` if the text
/// writes none of them (a value left to its default in a table the file does not open).
pub fn line_of(text: &str, key: &str) -> Option<usize> {
    let mut key = key;
    loop {
        if let Some(line) = written_at(text, key) {
            return Some(line);
        }
        key = &key[..key.rfind(['.', '['])?];
    }
}

/// The line whose key or table header is exactly `key`.
fn written_at(text: &str, key: &str) -> Option<usize> {
    let mut start = 0;
    for (n, line) in text.split_inclusive('\n').enumerate() {
        let body = strip_comment(line).trim();
        let at = if body.starts_with('[') {
            Some(start + line.len() - line.trim_start().len())
        } else if body.contains('=') && !starts_inside_value(body) {
            line.find('=').map(|eq| start + eq + 1)
        } else {
            None
        };
        if at.is_some_and(|at| key_path(text, at) == key) {
            return Some(n + 1);
        }
        start += line.len();
    }
    None
}

fn push(path: &mut String, key: &str) {
    if key.is_empty() {
        return;
    }
    if !path.is_empty() {
        path.push('.');
    }
    path.push_str(key);
}

fn strip_comment(line: &str) -> &str {
    let mut in_string = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => in_string = !in_string,
            '#' if !in_string => return &line[..i],
            _ => {}
        }
    }
    line
}

/// A continuation line of a multi-line array (`  0.7, 0.8,`) has no key of its own.
fn starts_inside_value(body: &str) -> bool {
    body.starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '+' || c == '{' || c == ']')
}

#[cfg(test)]
mod tests {
    use super::{key_path, line_of};

    const DOC: &str = "title = \"x\"\n[material]\nmu = 1\n[[study]]\nkind = \"uniaxial\"\n[[study]]\nkind = \"cylinder\"\nstretch = { from = 0.7, to = 1.6, stepp = 0.05 }\nvtk = [\n  0.7,\n  1.0 ]\n";

    fn at(needle: &str) -> String {
        key_path(DOC, DOC.find(needle).unwrap_or(0))
    }

    #[test]
    fn names_headers_array_indices_and_inline_keys() {
        assert_eq!(at("\"x\""), "title");
        assert_eq!(at("1\n[[study"), "material.mu");
        assert_eq!(at("\"uniaxial\""), "study[0].kind");
        assert_eq!(at("\"cylinder\""), "study[1].kind");
        assert_eq!(at("stepp"), "study[1].stretch.stepp");
        assert_eq!(at("1.6"), "study[1].stretch.to");
        assert_eq!(at("1.0 ]"), "study[1].vtk");
    }

    #[test]
    fn finds_the_line_of_a_key_or_of_what_encloses_it() {
        assert_eq!(line_of(DOC, "title"), Some(1));
        assert_eq!(line_of(DOC, "material.mu"), Some(3));
        assert_eq!(line_of(DOC, "material.alpha"), Some(2));
        assert_eq!(line_of(DOC, "study[0]"), Some(4));
        assert_eq!(line_of(DOC, "study[1].kind"), Some(7));
        assert_eq!(line_of(DOC, "study[1].stretch.step"), Some(8));
        assert_eq!(line_of(DOC, "study[1].vtk[1]"), Some(9));
        assert_eq!(line_of(DOC, "study[1].nr"), Some(6));
        assert_eq!(line_of(DOC, "activation.damage[0]"), None);
        assert_eq!(line_of(DOC, "(file)"), None);
    }

    #[test]
    fn counts_arrays_of_tables_inside_each_study() {
        let doc = "[[study]]\nkind = \"cylinder\"\n[[study.regions]]\nr = [0, 1]\n[[study.regions]]\ndamage = 2\n[[study]]\n[[study.regions]]\nactivation = 3\n";
        assert_eq!(line_of(doc, "study[0].regions[1].damage"), Some(6));
        assert_eq!(line_of(doc, "study[0].regions[0]"), Some(3));
        assert_eq!(line_of(doc, "study[1].regions[0].activation"), Some(9));
        assert_eq!(
            key_path(doc, doc.find("3").unwrap_or(0)),
            "study[1].regions[0].activation"
        );
    }
}
