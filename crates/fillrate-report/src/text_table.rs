//! Plain-text tables as `profile` and the fill-rate layer print them: the first column
//! left-aligned, the others right-aligned, two spaces apart.

/// The header line, then one line per row, every column as wide as its widest cell.
pub fn aligned_lines<R: AsRef<[String]>>(header: &[&str], rows: &[R]) -> Vec<String> {
    let widths: Vec<usize> = (0..header.len())
        .map(|c| {
            rows.iter().map(|r| r.as_ref().get(c).map_or(0, String::len)).chain([header[c].len()]).max().unwrap_or(0)
        })
        .collect();
    let line = |cells: &mut dyn Iterator<Item = &str>| {
        cells
            .zip(&widths)
            .enumerate()
            .map(|(c, (cell, &w))| if c == 0 { format!("{cell:<w$}") } else { format!("{cell:>w$}") })
            .collect::<Vec<_>>()
            .join("  ")
    };
    let mut lines = vec![line(&mut header.iter().copied())];
    lines.extend(rows.iter().map(|row| line(&mut row.as_ref().iter().map(String::as_str))));
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_take_their_widest_cell() {
        let rows = vec![vec!["scene".to_owned(), "12".to_owned()], vec!["a".to_owned(), "12345".to_owned()]];
        assert_eq!(aligned_lines(&["pass", "n"], &rows), ["pass       n", "scene     12", "a      12345"]);
    }
}
