//! Source locations: a scene file and a byte offset in it, turned into `file:line:col` only when
//! a message is written.
//!
//! Every directive and parameter keeps where it was written, so that errors and warnings can
//! point at it; most are never printed. A location therefore holds one shared [`SourceName`]
//! and a byte offset, and its line and column are found from the file's line starts (a binary
//! search) when they are asked for.

use std::fmt;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A scene file as locations in it need it: its name, the directory its relative file names
/// resolve against, and where its lines start, shared by every location in the file.
#[derive(Debug)]
pub struct SourceName {
    /// The file (`<string>` for [`crate::pbrt::parse_str`]).
    path: Arc<Path>,
    /// The directory of the scene file parsing started from, when known (pbrt-v4's search
    /// directory).
    search_dir: Option<Arc<Path>>,
    /// Where each line starts.
    line_starts: LineStarts,
    /// The byte offsets of the UTF-8 continuation bytes (the second and later bytes of a
    /// non-ASCII character), ascending: columns count characters, not bytes. Empty for ASCII
    /// text.
    continuations: Vec<usize>,
    /// The line and column of the one location made with them ([`Location::new`]), which has
    /// a name of its own.
    given: Option<(u32, u32)>,
}

impl SourceName {
    /// The name of `path` with text `text` (the text itself is not kept).
    pub fn new(path: Arc<Path>, search_dir: Option<Arc<Path>>, text: &str) -> Self {
        let bytes = text.as_bytes();
        let line_starts = LineStarts::new(bytes);
        let continuations = if text.is_ascii() {
            Vec::new()
        } else {
            bytes.iter().enumerate().filter(|(_, &b)| b & 0xc0 == 0x80).map(|(i, _)| i).collect()
        };
        Self { path, search_dir, line_starts, continuations, given: None }
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// A name without text for the one location at line `line` and column `col`.
    fn given(path: Arc<Path>, line: u32, col: u32) -> Self {
        let line_starts = LineStarts::Narrow(vec![0]);
        Self { path, search_dir: None, line_starts, continuations: Vec::new(), given: Some((line, col)) }
    }

    /// The 1-based line and column (in characters) of byte `offset` (a character boundary), or
    /// the ones given.
    fn line_col(&self, offset: usize) -> (u32, u32) {
        if let Some(given) = self.given {
            return given;
        }
        let (line, start) = self.line_starts.line_of(offset);
        let before = |at: usize| self.continuations.partition_point(|&c| c < at);
        let chars = offset - start - (before(offset) - before(start));
        (line as u32, chars as u32 + 1)
    }
}

/// The byte offset of each line's first byte, ascending (the first is 0): four bytes a line
/// in a file shorter than 4 GiB, eight in a longer one.
#[derive(Debug)]
enum LineStarts {
    Narrow(Vec<u32>),
    Wide(Vec<u64>),
}

impl LineStarts {
    fn new(bytes: &[u8]) -> Self {
        let starts = std::iter::once(0).chain(memchr::memchr_iter(b'\n', bytes).map(|i| i + 1));
        match u32::try_from(bytes.len()) {
            Ok(_) => Self::Narrow(starts.map(|s| s as u32).collect()),
            Err(_) => Self::Wide(starts.map(|s| s as u64).collect()),
        }
    }

    /// The 1-based line of byte `offset` and the offset its line starts at.
    fn line_of(&self, offset: usize) -> (usize, usize) {
        fn find<T: Copy + Into<u64>>(starts: &[T], offset: usize) -> (usize, usize) {
            let line = starts.partition_point(|&s| s.into() <= offset as u64).max(1);
            (line, starts[line - 1].into() as usize)
        }
        match self {
            Self::Narrow(v) => find(v, offset),
            Self::Wide(v) => find(v, offset),
        }
    }
}

/// A position in a scene file: 1-based line and column (columns count characters).
#[derive(Clone, Debug)]
pub struct Location {
    source: Arc<SourceName>,
    /// The byte offset in the file (line and column found when asked; unused for a location
    /// whose line and column were given as they are, such as one in a lens file).
    at: usize,
}

impl Location {
    /// Line `line` and column `col` of `file`.
    pub fn new(file: Arc<Path>, line: u32, col: u32) -> Self {
        Self { source: Arc::new(SourceName::given(file, line, col)), at: 0 }
    }

    /// Byte `offset` (a character boundary) of the file `source` names.
    pub fn at_offset(source: &Arc<SourceName>, offset: usize) -> Self {
        Self { source: source.clone(), at: offset }
    }

    /// The file.
    pub fn file(&self) -> &Path {
        &self.source.path
    }

    /// The directory of the scene file parsing started from, when known: relative file names
    /// resolve against it (pbrt-v4's search directory), whichever file wrote them.
    pub fn search_dir(&self) -> Option<&Path> {
        self.source.search_dir.as_deref()
    }

    /// The line and column, both 1-based.
    pub fn line_col(&self) -> (u32, u32) {
        self.source.line_col(self.at)
    }

    /// The line, starting at 1.
    pub fn line(&self) -> u32 {
        self.line_col().0
    }

    /// The column in characters, starting at 1.
    pub fn col(&self) -> u32 {
        self.line_col().1
    }

    /// The file a name written at this location means. As in pbrt-v4, a relative name is taken
    /// relative to the main scene file's directory ([`Location::search_dir`]); when nothing exists
    /// there but the name exists relative to the file that wrote it, that file is meant (names
    /// relative to the including file, which earlier versions of prism required). Absolute
    /// names are returned as they are.
    pub fn resolve(&self, name: impl AsRef<Path>) -> PathBuf {
        let name = name.as_ref();
        let local = self.file().parent().unwrap_or(Path::new("")).join(name);
        let Some(dir) = self.search_dir() else { return local };
        let main = dir.join(name);
        if name.is_absolute() || main.exists() || !local.exists() {
            main
        } else {
            local
        }
    }
}

impl PartialEq for Location {
    fn eq(&self, other: &Self) -> bool {
        self.file() == other.file() && self.line_col() == other.line_col() && self.search_dir() == other.search_dir()
    }
}

impl Eq for Location {}

impl Hash for Location {
    fn hash<H: Hasher>(&self, state: &mut H) {
        (self.file(), self.line_col(), self.search_dir()).hash(state);
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (line, col) = self.line_col();
        write!(f, "{}:{line}:{col}", self.file().display())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Line and column of byte `offset`, counted from the start of `text`.
    fn counted(text: &str, offset: usize) -> (u32, u32) {
        let before = &text[..offset];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        (before.matches('\n').count() as u32 + 1, before[line_start..].chars().count() as u32 + 1)
    }

    #[test]
    fn every_offset_has_the_counted_line_and_column() {
        for text in ["", "\n", "a bb\n\n  λ \"é\" c\r\n[ 1\t2 ]   \u{2003}d\ne", "ü\n\nx€y\n"] {
            let name = Arc::new(SourceName::new(Arc::from(Path::new("t.pbrt")), None, text));
            for o in text.char_indices().map(|(i, _)| i).chain([text.len()]) {
                assert_eq!(Location::at_offset(&name, o).line_col(), counted(text, o), "{text:?} at {o}");
            }
        }
    }

    #[test]
    fn given_lines_and_columns_are_kept_and_compare_with_counted_ones() {
        let given = Location::new(Arc::from(Path::new("t.pbrt")), 2, 3);
        assert_eq!(given.to_string(), "t.pbrt:2:3");
        let name = Arc::new(SourceName::new(Arc::from(Path::new("t.pbrt")), None, "a\n  b"));
        assert_eq!(Location::at_offset(&name, 4), given);
    }
}
