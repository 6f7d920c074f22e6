//! README.md's "Using it" block is what a reader types: each `prism` line there must parse with
//! prism's own command line, and each other program's line must name a file the repository has.

use clap::Parser;
use prism::cli::Cli;
use std::path::Path;

/// The lines of the first ```sh block after the heading `## Using it`.
fn using_it_lines(readme: &str) -> Vec<String> {
    let section = readme.split("\n## Using it\n").nth(1).expect("README has a \"## Using it\" section");
    let block = section.split("```sh\n").nth(1).expect("a ```sh block in \"Using it\"");
    let block = block.split("\n```").next().expect("the block ends");
    block.lines().map(str::to_string).collect()
}

/// A command line without its `# comment`, split at whitespace (the README quotes nothing;
/// globs such as `part*.film` are passed on as written).
fn words(line: &str) -> Vec<&str> {
    line.split('#').next().unwrap_or("").split_whitespace().collect()
}

/// Parses a `prism …` line with prism's command line.
fn parse(line: &str) -> Result<Cli, clap::Error> {
    Cli::try_parse_from(words(line))
}

#[test]
fn every_command_line_in_the_readme_parses() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let lines = using_it_lines(&readme);
    let mut prism_lines = 0;
    for line in lines.iter().filter(|l| !l.trim().is_empty()) {
        let w = words(line);
        match w.first().copied() {
            Some("prism") => {
                prism_lines += 1;
                if let Err(e) = parse(line) {
                    panic!("README line does not parse: {line}\n{e}");
                }
            }
            // Another program's line: the script it runs is in the repository.
            Some("bash") => assert!(root.join(w[1]).is_file(), "README runs {}, which does not exist", w[1]),
            _ => panic!("README line of an unknown program: {line}"),
        }
    }
    assert!(prism_lines >= 10, "only {prism_lines} prism lines found in \"Using it\"");
    // The check can fail: an unknown flag, a missing value and an unknown subcommand are refused.
    assert!(parse("prism render --no-such-flag 3   # a comment").is_err());
    assert!(parse("prism render --spp").is_err());
    assert!(parse("prism frobnicate").is_err());
    assert!(parse("prism merge part*.film -o merged.exr   # a glob is one word").is_ok());
}
