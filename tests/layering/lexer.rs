//! Rust source as tokens, without comments, strings and character literals.

#[derive(Debug, Clone, PartialEq)]
pub enum Tok {
    Ident(String),
    /// `::`
    PathSep,
    Punct(char),
}

#[derive(Debug, Clone)]
pub struct Token {
    pub tok: Tok,
    pub line: usize,
}

pub fn tokens(source: &str) -> Vec<Token> {
    let chars: Vec<char> = source.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    // Skips from `i` to `end`, counting the lines skipped.
    let skip = |i: &mut usize, line: &mut usize, end: usize| {
        *line += chars[*i..end.min(chars.len())].iter().filter(|c| **c == '\n').count();
        *i = end.min(chars.len());
    };
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            let end = chars[i..].iter().position(|c| *c == '\n').map_or(chars.len(), |p| i + p);
            skip(&mut i, &mut line, end);
        } else if c == '/' && next == Some('*') {
            let end = block_comment_end(&chars, i);
            skip(&mut i, &mut line, end);
        } else if c == '"' {
            let end = string_end(&chars, i + 1);
            skip(&mut i, &mut line, end);
        } else if c == '\'' {
            let end = char_literal_end(&chars, i);
            skip(&mut i, &mut line, end);
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let word: String = chars[start..i].iter().collect();
            let after = chars.get(i).copied();
            let is_string_prefix = matches!(word.as_str(), "r" | "b" | "br" | "c" | "cr");
            if is_string_prefix && after == Some('"') {
                let end = string_end(&chars, i + 1);
                skip(&mut i, &mut line, end);
            } else if is_string_prefix && word != "b" && word != "c" && after == Some('#') {
                let hashes = chars[i..].iter().take_while(|c| **c == '#').count();
                if chars.get(i + hashes) == Some(&'"') {
                    let end = raw_string_end(&chars, i + hashes + 1, hashes);
                    skip(&mut i, &mut line, end);
                } else {
                    i += 1; // r#ident: the identifier follows
                }
            } else if word == "b" && after == Some('\'') {
                let end = char_literal_end(&chars, i);
                skip(&mut i, &mut line, end);
            } else {
                out.push(Token { tok: Tok::Ident(word), line });
            }
        } else if c.is_ascii_digit() {
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
        } else if c == ':' && next == Some(':') {
            out.push(Token { tok: Tok::PathSep, line });
            i += 2;
        } else {
            if c == '\n' {
                line += 1;
            } else if !c.is_whitespace() {
                out.push(Token { tok: Tok::Punct(c), line });
            }
            i += 1;
        }
    }
    out
}

/// Just past the `*/` closing the (nestable) block comment opened at `start`.
fn block_comment_end(chars: &[char], start: usize) -> usize {
    let (mut depth, mut i) = (0, start);
    while i + 1 < chars.len() {
        match (chars[i], chars[i + 1]) {
            ('/', '*') => (depth, i) = (depth + 1, i + 2),
            ('*', '/') => {
                (depth, i) = (depth - 1, i + 2);
                if depth == 0 {
                    return i;
                }
            }
            _ => i += 1,
        }
    }
    chars.len()
}

/// Just past the closing quote of a string whose text starts at `i`.
fn string_end(chars: &[char], mut i: usize) -> usize {
    while i < chars.len() {
        match chars[i] {
            '\\' => i += 2,
            '"' => return i + 1,
            _ => i += 1,
        }
    }
    chars.len()
}

/// Just past the `"###` closing a raw string whose text starts at `i`.
fn raw_string_end(chars: &[char], mut i: usize, hashes: usize) -> usize {
    while i < chars.len() {
        if chars[i] == '"' && chars[i + 1..].iter().take(hashes).filter(|c| **c == '#').count() == hashes {
            return i + 1 + hashes;
        }
        i += 1;
    }
    chars.len()
}

/// At a `'`: just past the character literal it opens, or just past the `'` of a lifetime
/// or label (whose name is then read as an identifier).
fn char_literal_end(chars: &[char], start: usize) -> usize {
    match (chars.get(start + 1), chars.get(start + 2)) {
        (Some('\\'), _) => {
            let close = chars[start + 3..].iter().position(|c| *c == '\'');
            close.map_or(chars.len(), |p| start + 3 + p + 1)
        }
        (Some(_), Some('\'')) => start + 3,
        _ => start + 1,
    }
}
