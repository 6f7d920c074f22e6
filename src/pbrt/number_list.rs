//! Numbers in the scene format: a word read as a number ([`read_float`], [`read_int`]), and a
//! bracketed list of numbers read straight from the file's text, without a token per value, and
//! by all threads when it is long ([`read`]).
//!
//! A mesh written inline (`"point3 P" [ … ]`, `"integer indices" [ … ]`) is most of a big text
//! scene. Between its brackets the pbrt-v4 format allows only numbers and blanks (a string or a
//! comment in the list is read token by token instead, [`super::tokenizer::Tokenizer::number_span`]),
//! so the list splits into independent pieces at any blank: each piece is read by one thread,
//! and the values are joined in the file's order. A bad number is reported as the token path
//! reports it: the first one in the file, at its line and column. A transform's numbers
//! (`Transform [ … ]`, `Translate x y z`: one or more per instance in a scene of many) are read
//! from the text too ([`read_exactly`]); numbers that are not exactly the transform's go to the
//! tokens, which say what is wrong.

use rayon::prelude::*;

use super::error::SceneError;
use super::tokenizer::{is_blank, NumberSpan};

/// Lists shorter than this [bytes] are read by one thread.
const MIN_PARALLEL_BYTES: usize = 1 << 20;

/// The text a thread reads at least [bytes].
const MIN_PIECE_BYTES: usize = 1 << 18;

/// The numbers of a list, read as the parameter's type asks.
#[derive(Debug, PartialEq)]
pub enum Numbers {
    /// Every value read as a finite `f32`.
    Floats(Vec<f32>),
    /// Every value read as an `i32`.
    Integers(Vec<i32>),
}

impl Numbers {
    /// How many values.
    pub fn len(&self) -> usize {
        match self {
            Self::Floats(v) => v.len(),
            Self::Integers(v) => v.len(),
        }
    }

    /// Whether the list is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Which numbers a parameter type holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NumberKind {
    /// Floating point values ("float", points, vectors, normals).
    Float,
    /// "integer" values.
    Integer,
}

/// The values of `span`, each read as `kind`.
pub fn read(span: &NumberSpan, kind: NumberKind) -> Result<Numbers, SceneError> {
    match kind {
        NumberKind::Float => read_words(span, read_float).map(Numbers::Floats),
        NumberKind::Integer => read_words(span, read_int).map(Numbers::Integers),
    }
}

/// Fills `out` with the words of `text` read as [`read_float`] reads a word; false when there
/// are more or fewer words than `out` holds or one is not a number.
pub(super) fn read_exactly(text: &str, out: &mut [f32]) -> bool {
    let mut words = text.split(|c: char| c.is_ascii() && is_blank(c as u8)).filter(|w| !w.is_empty());
    for x in out {
        match words.next().map(read_float) {
            Some(Ok(v)) => *x = v,
            _ => return false,
        }
    }
    words.next().is_none()
}

/// A word that is not a number: its byte offset in the file and the message.
type BadWord = (usize, &'static str);

/// The words of `span`, each read by `read`: in pieces by all threads when it is long.
fn read_words<T: Send>(
    span: &NumberSpan,
    read: impl Fn(&str) -> Result<T, &'static str> + Sync,
) -> Result<Vec<T>, SceneError> {
    let text = span.text;
    let bad = |(offset, message): BadWord| {
        let word = text[offset - span.offset..].split(|c: char| is_blank(c as u8)).next().unwrap_or_default();
        SceneError::syntax(&span.file.location(offset), word, message)
    };
    let pieces = pieces(text.as_bytes(), rayon::current_num_threads());
    if pieces.len() == 1 {
        let mut values = read_piece(text, span.offset, &read).map_err(bad)?;
        values.shrink_to_fit();
        return Ok(values);
    }
    let read_pieces: Vec<Result<Vec<T>, BadWord>> =
        pieces.par_iter().map(|&(a, b)| read_piece(&text[a..b], span.offset + a, &read)).collect();
    let mut values = Vec::with_capacity(read_pieces.iter().map(|p| p.as_ref().map_or(0, Vec::len)).sum());
    for piece in read_pieces {
        values.extend(piece.map_err(bad)?);
    }
    Ok(values)
}

/// `bytes` cut at blanks into pieces of at least [`MIN_PIECE_BYTES`], about four per thread;
/// one piece when the list is shorter than [`MIN_PARALLEL_BYTES`].
fn pieces(bytes: &[u8], threads: usize) -> Vec<(usize, usize)> {
    if bytes.len() < MIN_PARALLEL_BYTES || threads < 2 {
        return vec![(0, bytes.len())];
    }
    let n = (4 * threads).min(bytes.len() / MIN_PIECE_BYTES).max(1);
    let mut cuts = vec![0];
    for k in 1..n {
        let mut at = (k * bytes.len() / n).max(*cuts.last().unwrap_or(&0));
        while at < bytes.len() && !is_blank(bytes[at]) {
            at += 1;
        }
        cuts.push(at);
    }
    cuts.push(bytes.len());
    cuts.dedup();
    cuts.windows(2).map(|w| (w[0], w[1])).collect()
}

/// The words of `text` (ASCII), which starts at byte `offset` of its file, each read by `read`;
/// the first that `read` refuses, as a [`BadWord`].
fn read_piece<T>(
    text: &str,
    offset: usize,
    read: &impl Fn(&str) -> Result<T, &'static str>,
) -> Result<Vec<T>, BadWord> {
    let bytes = text.as_bytes();
    let mut values = Vec::with_capacity(bytes.len() / 8);
    let mut i = 0;
    while i < bytes.len() {
        if is_blank(bytes[i]) {
            i += 1;
            continue;
        }
        let start = i;
        while i < bytes.len() && !is_blank(bytes[i]) {
            i += 1;
        }
        match read(&text[start..i]) {
            Ok(v) => values.push(v),
            Err(message) => return Err((offset + start, message)),
        }
    }
    Ok(values)
}

/// `word` as a finite `f32`, or why it is not one.
pub(super) fn read_float(word: &str) -> Result<f32, &'static str> {
    match short_decimal(word).map_or_else(|| word.parse::<f32>(), Ok) {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err("number is not finite"),
        Err(_) => Err("expected a number"),
    }
}

/// `s` as an `f32` when it is a short plain decimal, `-?digits` or `-?digits.digits` whose
/// digits read as an integer make at most 2²⁴ with at most 10 of them after the point; `None`
/// for anything else. The integer and the power of ten are then both exact in `f32`, and their
/// quotient, one correctly rounded division, is the correctly rounded value of `s` (Clinger,
/// "How to read floating point numbers accurately", 1990): what `str::parse` returns, found
/// without its general machinery for the numbers scene files are mostly made of.
fn short_decimal(s: &str) -> Option<f32> {
    const POW10: [f32; 11] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10];
    let (negative, digits) = match s.as_bytes() {
        [b'-', rest @ ..] => (true, rest),
        all => (false, all),
    };
    let (mut m, mut after_point) = (0u32, None::<usize>);
    for (i, &b) in digits.iter().enumerate() {
        match b {
            b'0'..=b'9' => {
                m = m * 10 + u32::from(b - b'0');
                if m > 1 << 24 {
                    return None;
                }
                if let Some(k) = &mut after_point {
                    *k += 1;
                }
            }
            b'.' if i > 0 && after_point.is_none() => after_point = Some(0),
            _ => return None,
        }
    }
    let k = match after_point {
        None if !digits.is_empty() => 0,
        Some(k @ 1..=10) => k,
        _ => return None,
    };
    let v = m as f32 / POW10[k];
    Some(if negative { -v } else { v })
}

/// `word` as an `i32`, or why it is not one.
pub(super) fn read_int(word: &str) -> Result<i32, &'static str> {
    // Nine digits or fewer fit an i32 whatever they are: read them without the general parser.
    let (negative, digits) = match word.as_bytes() {
        [b'-', rest @ ..] => (true, rest),
        all => (false, all),
    };
    if (1..=9).contains(&digits.len()) && digits.iter().all(u8::is_ascii_digit) {
        let m = digits.iter().fold(0, |m, &d| 10 * m + i32::from(d - b'0'));
        return Ok(if negative { -m } else { m });
    }
    match word.parse::<i64>() {
        Ok(v) => i32::try_from(v).map_err(|_| "integer out of range"),
        Err(_) => Err("expected an integer"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::tokenizer::{SourceFile, Tokenizer};
    use std::path::Path;
    use std::sync::Arc;

    fn file(text: String) -> SourceFile {
        SourceFile::new(Arc::from(Path::new("n.pbrt")), None, text)
    }

    /// The span after the file's first `[`.
    fn span_of(f: &SourceFile) -> Option<NumberSpan<'_>> {
        let mut t = Tokenizer::new(f);
        while t.next_token().unwrap()?.text != "[" {}
        t.number_span()
    }

    #[test]
    fn short_decimals_read_as_str_parse_reads_them() {
        // Digits from a fixed linear congruential sequence, with and without sign, leading zeros
        // and points, against the standard library's correctly rounded reading.
        let mut state = 0x2545_f491_u64;
        let mut next = |n: u64| {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 33) % n
        };
        for _ in 0..200_000 {
            let m = next(1 << 25);
            let k = next(12) as usize;
            let digits = format!("{}{m:0>width$}", "0".repeat(next(3) as usize), width = k + 1);
            let (int, frac) = digits.split_at(digits.len() - k);
            let sign = if next(2) == 0 { "-" } else { "" };
            let s = if k == 0 { format!("{sign}{int}") } else { format!("{sign}{int}.{frac}") };
            let want: f32 = s.parse().unwrap();
            match short_decimal(&s) {
                Some(v) => assert_eq!(v.to_bits(), want.to_bits(), "{s}"),
                None => assert!(m > 1 << 24 || k > 10, "{s} not read"),
            }
        }
        assert_eq!(short_decimal("16777216"), Some(16_777_216.0));
        assert_eq!(short_decimal("-0").map(f32::to_bits), Some((-0.0f32).to_bits()));
        for other in ["", "-", ".5", "5.", "1e3", "+1", "1.2.3", "16777217", "0.00000000001", "inf", "nan", "1_0"] {
            assert_eq!(short_decimal(other), None, "{other}");
        }
    }

    #[test]
    fn pieces_cut_at_blanks_and_cover_the_text() {
        let text: String = (0..400_000).map(|i| format!("{i}{}", if i % 7 == 0 { "\n" } else { " " })).collect();
        let p = pieces(text.as_bytes(), 2);
        assert!(p.len() > 1, "{p:?}");
        assert_eq!((p[0].0, p[p.len() - 1].1), (0, text.len()));
        for w in p.windows(2) {
            assert_eq!(w[0].1, w[1].0);
            assert!(is_blank(text.as_bytes()[w[0].1]), "cut inside a word at {}", w[0].1);
        }
        assert_eq!(pieces(b"1 2 3", 8), vec![(0, 5)]);
    }

    #[test]
    fn a_long_list_read_in_pieces_equals_the_values_written() {
        // Every value distinct, integers and decimals written as pbrt exporters write them.
        let n = 300_000;
        let ints: String = (0..n).map(|i| format!("{} ", i * 3 - 7)).collect();
        let f = file(format!("\"integer indices\" [ {ints}\n]"));
        let s = span_of(&f).unwrap();
        assert!(s.text.len() > MIN_PARALLEL_BYTES);
        let want: Vec<i32> = (0..n).map(|i| i * 3 - 7).collect();
        assert_eq!(read(&s, NumberKind::Integer).unwrap(), Numbers::Integers(want));

        let floats: String = (0..n).map(|i| format!("{:.6}\t", i as f64 * 1e-3 - 2.5)).collect();
        let f = file(format!("\"point3 P\" [{floats}]"));
        let s = span_of(&f).unwrap();
        let want: Vec<f32> = (0..n).map(|i| format!("{:.6}", i as f64 * 1e-3 - 2.5).parse().unwrap()).collect();
        assert_eq!(read(&s, NumberKind::Float).unwrap(), Numbers::Floats(want));
    }

    #[test]
    fn the_first_bad_word_in_the_file_is_the_error_at_its_place() {
        let mut text: String = (0..300_000).map(|i| format!("{i} ")).collect();
        text.push_str("\n  1x 2 ");
        text.push_str(&"7 ".repeat(300_000));
        text.push_str("nan 3");
        let f = file(format!("\"float v\" [\n{text}]"));
        let e = read(&span_of(&f).unwrap(), NumberKind::Float).unwrap_err();
        assert_eq!(e.to_string(), "n.pbrt:3:3: expected a number (at \"1x\")");
        let f = file("\"integer i\" [ 1 2\n 3000000000 ]".to_string());
        let e = read(&span_of(&f).unwrap(), NumberKind::Integer).unwrap_err();
        assert_eq!(e.to_string(), "n.pbrt:2:2: integer out of range (at \"3000000000\")");
    }

    /// The first parameter of the list `text`, or its error, read through the parser's stream.
    fn first_param(text: &str) -> Result<crate::pbrt::ParamValue, String> {
        let store = crate::pbrt::tokenizer::SourceFiles::default();
        let mut src = crate::pbrt::source::Source::new(&store, file(text.to_string()), "n.pbrt".into());
        let ps = src.params("srgb").map_err(|e| e.to_string())?;
        let value = ps.iter().next().expect("one parameter").value.clone();
        Ok(value)
    }

    #[test]
    fn lists_read_from_the_text_equal_lists_read_as_tokens() {
        // A comment before the `]` sends the same list through the tokens.
        for (decl, values) in [
            ("float f", "1 -2.5 3e2 .5 +4"),
            ("integer i", "0 -7 123456789 1234567890 -2147483648"),
            ("point3 P", "0 0 0 1 0 0 0 1 0"),
            ("normal N", "0 0 1"),
            ("point2 uv", "0 0 1 1"),
            ("vector2 v", "1 2 3"),
            ("point3 P", "1 2"),
            ("float f", ""),
            ("float f", "1 inf"),
            ("float f", "1 1e39"),
            ("integer i", "1 2.5"),
            ("integer i", "2147483648"),
            ("float", "1"),
        ] {
            let text = format!("\"{decl}\" [ {values} ]");
            let tokens = format!("\"{decl}\" [ {values} # as tokens\n ]");
            assert!(file(text.clone()).text().contains(']'));
            assert_eq!(first_param(&text), first_param(&tokens), "{text}");
        }
        assert_eq!(first_param("\"integer i\" [ 7 ]"), Ok(crate::pbrt::ParamValue::Integer(vec![7])));
    }

    #[test]
    fn strings_comments_and_brackets_leave_the_list_to_the_tokens() {
        for text in ["[ 1 \"2\" ]", "[ 1 # a ] in a comment\n 2 ]", "[ 1 [ 2 ] ]", "[ 1 2", "[ 1 λ 2 ]"] {
            assert!(span_of(&file(text.to_string())).is_none(), "{text}");
        }
        let f = file("[ 1\u{b}2\u{c}3 ] x".to_string());
        let s = span_of(&f).unwrap();
        assert_eq!(read(&s, NumberKind::Float).unwrap(), Numbers::Floats(vec![1.0, 2.0, 3.0]));
    }
}
