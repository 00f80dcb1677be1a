//! Tire Test Consortium (TTC) run files, each a whole test programme read as one run (the
//! method's preparation later cuts it into its test blocks): the ASCII `.dat` files read here,
//! and the MATLAB `.mat` files (see [`super::mat`]) through the same channel code.
//!
//! **ASCII layout.** Line 1 is a title, line 2 the channel names, line 3 their units, then one
//! row of numbers per sample. Shipped files are tab-separated and unit entries may contain a
//! blank (`deg c`), e.g.
//!
//! ```text
//! Tire_Name=Hoosier 43075 16x7.5-10 R25B; Rim_Width=7; Run 071
//! ET  V   N   SA  IA  RL  RE  P   FX  FY  FZ  MX  MZ  NFX  NFY  RST    TSTI   ...  SR
//! s   kph rpm deg deg cm  cm  kPa N   N   N   Nm  Nm  none none deg c  deg c  ...  SAE
//! ```
//!
//! or `sec ... N-m N-m ... deg C ... none none` with `SL` after `SR`. When the name and unit
//! lines are tab-separated the tabs split them; otherwise the unit line's words are grouped
//! into known units ([`crate::io::units::is_known`]; two-word units such as `deg C` first), and a
//! line with as many words as channels is taken one word per channel. Data rows may be
//! separated by tabs or blanks.
//!
//! **Channels used** (names ignore case; the others are listed in a note):
//!
//! | quantity    | channel | usual unit |
//! |-------------|---------|------------|
//! | time        | `ET`    | s          |
//! | speed       | `V`     | kph (mph)  |
//! | Fz          | `FZ`    | N (lb)     |
//! | alpha       | `SA`    | deg        |
//! | kappa       | `SR`, else `SL` | SAE, none (a plain ratio) |
//! | gamma       | `IA`    | deg        |
//! | pressure    | `P`     | kPa (psi)  |
//! | temperature | mean of `TSTI`, `TSTC`, `TSTO` (tread surface inside, centre, outside), else `TSTC` | deg C (deg F) |
//! | Fx, Fy, Mz  | `FX`, `FY`, `MZ` | N, Nm (lb, ft-lb) |
//!
//! `SR` is TTC's slip ratio from the effective rolling radius, `SL` the one from the loaded
//! radius; which one was read is noted. `AMBTMP` is the ambient temperature, never the tread's.
//!
//! **Axes.** TTC data are in SAE axes (x forward, y right, z down): a positive slip angle gives
//! a negative lateral force, and the load is a negative `FZ`. tire-gap works in the axes of
//! the 1987 paper (x forward, y right, z down, alpha > 0 giving Fy > 0): the y and z axes are
//! the same, the slip angle's sign is not. So `alpha = -SA`, `Fz = -FZ`, and camber, slip
//! ratio, Fx, Fy and Mz keep their sign (see [`sae_to_paper`]). If the median of `FZ` is
//! positive, the file already gives the load positive and it is kept (noted). A title naming
//! another `Coordinate_System` than SAE is refused.
//!
//! **Run id.** The integer after `run` in the file name (`B1464run23.dat` -> 23), else in the
//! title (`Run 071` -> 71), else 1.
//!
//! **Tire.** From the title's `Tire_Name=` (with its `Rim_Width=`, written as TTC's MAT-files
//! write `tireid`: `NAME, 7 inch rim`); a free-text title is the tire's name once the run text
//! (`Run 071`, `run23`) and a `Data from ... .mat` wrapper are removed; a bare test programme
//! code such as `B1464` names no tire. Several files are one data set through
//! [`super::merge`], which refuses files of different tires.

use std::path::Path;

use super::table::{self, Table};
use super::{InputError, Loaded};
use crate::data::Quantity;
use crate::io::units;
use crate::quantiles::{median, quantile};

/// TTC channel names per quantity, by preference (tread temperature is handled apart).
const CHANNELS: &[(Quantity, &[&str])] = &[
    (Quantity::Time, &["ET"]),
    (Quantity::Speed, &["V"]),
    (Quantity::Fz, &["FZ"]),
    (Quantity::Alpha, &["SA"]),
    (Quantity::Kappa, &["SR", "SL"]),
    (Quantity::Gamma, &["IA"]),
    (Quantity::Pressure, &["P"]),
    (Quantity::Fx, &["FX"]),
    (Quantity::Fy, &["FY"]),
    (Quantity::Mz, &["MZ"]),
];

/// Tread surface temperatures: inside, centre, outside.
const TREAD: [&str; 3] = ["TSTI", "TSTC", "TSTO"];

/// TTC's channels with their SI units (what a MAT-file without a channel list is assumed to
/// hold).
pub(crate) const SI_UNITS: &[(&str, &str)] = &[
    ("ET", "s"),
    ("V", "kph"),
    ("N", "rpm"),
    ("SA", "deg"),
    ("IA", "deg"),
    ("RL", "cm"),
    ("RE", "cm"),
    ("P", "kPa"),
    ("FX", "N"),
    ("FY", "N"),
    ("FZ", "N"),
    ("MX", "Nm"),
    ("MZ", "Nm"),
    ("NFX", "none"),
    ("NFY", "none"),
    ("RST", "degC"),
    ("TSTI", "degC"),
    ("TSTC", "degC"),
    ("TSTO", "degC"),
    ("AMBTMP", "degC"),
    ("SR", "none"),
    ("SL", "none"),
];

/// Whether `name` is the TTC channel `channel`: the same name ignoring case, or with a
/// number appended (`ET1`, `FX1`: the names a common re-save gives the channels).
pub(crate) fn names_channel(name: &str, channel: &str) -> bool {
    let Some((base, digits)) = name.split_at_checked(channel.len()) else {
        return false;
    };
    base.eq_ignore_ascii_case(channel) && digits.chars().all(|c| c.is_ascii_digit())
}

/// The TTC channel `name` is (see [`names_channel`]), if any.
pub(crate) fn canonical_of(name: &str) -> Option<&'static str> {
    SI_UNITS
        .iter()
        .map(|(c, _)| *c)
        .filter(|c| names_channel(name, c))
        .max_by_key(|c| c.len())
}

/// The position of channel `channel` among `names`: the name itself (ignoring case), else
/// the name with the smallest number appended.
fn position_of(names: &[String], channel: &str) -> Option<usize> {
    names
        .iter()
        .position(|x| x.eq_ignore_ascii_case(channel))
        .or_else(|| {
            names
                .iter()
                .enumerate()
                .filter(|(_, x)| names_channel(x, channel))
                .min_by_key(|(_, x)| x[channel.len()..].parse::<u64>().unwrap_or(u64::MAX))
                .map(|(i, _)| i)
        })
}

/// The preferred channel name of each quantity.
pub fn channel_name(q: Quantity) -> &'static str {
    match q {
        Quantity::Temperature => "TSTC",
        _ => CHANNELS
            .iter()
            .find(|(k, _)| *k == q)
            .map_or("run", |(_, names)| names[0]),
    }
}

const SPELLING: table::Spelling = table::Spelling {
    fz_missing: ("FZ", "channel FZ, the vertical load"),
    name: channel_name,
};

/// Whether `text` looks like a TTC run file: a second line naming `FZ` and a slip channel
/// (`SA`, `SR` or `SL`) and a third line giving each channel a unit.
pub fn looks_like(text: &str) -> bool {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty()).skip(1);
    let (Some(names), Some(units)) = (lines.next(), lines.next()) else {
        return false;
    };
    let Ok(names) = channel_names(names) else {
        return false;
    };
    let has = |n: &str| names.iter().any(|x| x.eq_ignore_ascii_case(n));
    has("FZ") && ["SA", "SR", "SL"].iter().any(|n| has(n)) && unit_entries(units, &names).is_ok()
}

/// The SAE sign convention of TTC data mapped to the paper's axes, per quantity: the factor
/// a value is multiplied by (the load's sign is decided from the data, see the module doc).
pub fn sae_to_paper(q: Quantity) -> f64 {
    match q {
        Quantity::Alpha => -1.0,
        _ => 1.0,
    }
}

/// The channel names of a name line: split at tabs when it has any, else at blanks.
fn channel_names(line: &str) -> Result<Vec<String>, String> {
    let line = line.trim_end();
    if !line.contains('\t') {
        return Ok(line.split_whitespace().map(str::to_string).collect());
    }
    let names: Vec<String> = line
        .trim_start()
        .split('\t')
        .map(|n| n.trim().to_string())
        .collect();
    match names.iter().position(String::is_empty) {
        Some(k) => Err(format!(
            "channel {} has no name (two tabs in a row in the channel-name line)",
            k + 1
        )),
        None => Ok(names),
    }
}

/// The unit of each channel from a unit line (see the module doc): tab-separated entries
/// when the line has as many; else the words grouped into known units, two-word units first;
/// else one word per channel when there are as many. The error names the entry at fault.
fn unit_entries(line: &str, names: &[String]) -> Result<Vec<String>, String> {
    let n = names.len();
    let line = line.trim_end_matches(['\r', '\n']);
    if line.contains('\t') {
        let mut fields: Vec<String> = line.split('\t').map(|u| u.trim().to_string()).collect();
        while fields.len() > n && fields.last().is_some_and(String::is_empty) {
            fields.pop();
        }
        if fields.len() == n && fields.iter().all(|f| !f.is_empty()) {
            return Ok(fields);
        }
    }
    let words: Vec<&str> = line.split_whitespace().collect();
    if let Some(units) = group_units(&words, n) {
        return Ok(units);
    }
    if words.len() == n {
        return Ok(words.iter().map(|w| w.to_string()).collect());
    }
    // Two-word units first, without backing off (the only grouping tried for very long
    // lines); else where the line stops matching: the first word that is no known unit, with
    // the channel it would belong to if the units before it are right.
    let mut grouped = Vec::new();
    let mut i = 0;
    while i < words.len() {
        let entry = grouped.len();
        let width = if i + 1 < words.len() && units::is_known(&words[i..i + 2].join(" ")) {
            2
        } else if units::is_known(words[i]) {
            1
        } else {
            let channel = names
                .get(entry)
                .map_or("beyond the last channel".to_string(), |c| {
                    format!(
                        "where channel {c} (entry {}) should have its unit",
                        entry + 1
                    )
                });
            return Err(format!(
                "the unit line does not give one unit per channel: \"{}\" (word {}) is not a \
                 known unit, {channel}; {} channels: {}",
                words[i],
                i + 1,
                n,
                listed(names)
            ));
        };
        grouped.push(words[i..i + width].join(" "));
        i += width;
    }
    if grouped.len() == n {
        return Ok(grouped);
    }
    Err(format!(
        "the unit line gives {} units for {n} channels ({}): one unit per channel is needed",
        grouped.len(),
        listed(names)
    ))
}

/// Channel names for a message: all of them up to 40, else the first 40 and a count.
fn listed(names: &[String]) -> String {
    match names.len() {
        ..=40 => names.join(" "),
        n => format!("{} ... ({n} in all)", names[..40].join(" ")),
    }
}

/// Splits `words` into exactly `n` known units, preferring two-word units (`deg C`) where
/// both splits are possible; `None` if no split gives `n`, or for lines of more than
/// [`MAX_GROUPED`] channels (the search's depth and table grow with the line).
fn group_units(words: &[&str], n: usize) -> Option<Vec<String>> {
    if n > MAX_GROUPED || words.len() > 2 * n || words.len() < n {
        return None;
    }
    // failed[i][k]: no split of words[i..] into n - k units.
    let mut failed = vec![vec![false; n + 1]; words.len() + 1];
    let mut out = Vec::with_capacity(n);
    fn go(
        words: &[&str],
        i: usize,
        n: usize,
        out: &mut Vec<String>,
        failed: &mut [Vec<bool>],
    ) -> bool {
        let k = out.len();
        if i == words.len() {
            return k == n;
        }
        if k == n || failed[i][k] {
            return false;
        }
        for width in [2, 1] {
            if i + width > words.len() {
                continue;
            }
            let unit = words[i..i + width].join(" ");
            if units::is_known(&unit) {
                out.push(unit);
                if go(words, i + width, n, out, failed) {
                    return true;
                }
                out.pop();
            }
        }
        failed[i][k] = true;
        false
    }
    go(words, 0, n, &mut out, &mut failed).then_some(out)
}

/// The most channels whose unit line is grouped into multi-word units (TTC files have about
/// 22); longer lines are read one word per channel.
const MAX_GROUPED: usize = 1000;

/// The integer following `run` (any case) in `text`, if any.
pub(crate) fn run_number(text: &str) -> Option<i64> {
    let lower = text.to_ascii_lowercase();
    lower.match_indices("run").find_map(|(at, _)| {
        let digits: String = lower[at + 3..]
            .chars()
            .skip_while(|c| *c == '_' || *c == ' ')
            .take_while(char::is_ascii_digit)
            .collect();
        digits.parse().ok()
    })
}

/// `text` without its run-number text (`Run 071`, `run23`, `RUN_4`) where `run` does not
/// continue a word.
fn strip_run(text: &str) -> String {
    let lower = text.to_ascii_lowercase();
    let bytes = lower.as_bytes();
    let mut out = String::new();
    let mut from = 0;
    for (at, _) in lower.match_indices("run") {
        if at < from || (at > 0 && bytes[at - 1].is_ascii_alphabetic()) {
            continue;
        }
        let mut end = at + 3;
        while end < bytes.len() && matches!(bytes[end], b' ' | b'_' | b'#' | b'-') {
            end += 1;
        }
        let digits = bytes[end..]
            .iter()
            .take_while(|b| b.is_ascii_digit())
            .count();
        if digits > 0 {
            out.push_str(&text[from..at]);
            from = end + digits;
        }
    }
    out.push_str(&text[from..]);
    out
}

/// A TTC test programme code such as `B1464`: one or two letters, then digits.
fn is_programme_code(s: &str) -> bool {
    let letters = s.chars().take_while(char::is_ascii_alphabetic).count();
    let rest = &s[letters..];
    (1..=2).contains(&letters) && !rest.is_empty() && rest.chars().all(|c| c.is_ascii_digit())
}

/// `text` with its runs of blanks made single blanks and its ends trimmed.
/// Where a character of the text could not be decoded (U+FFFD, e.g. a trademark sign saved in
/// a code page), it says nothing and is left out: the same name reads the same from every
/// encoding of the file.
fn collapse(text: &str) -> String {
    text.split(|c: char| c.is_whitespace())
        .map(|word| word.replace(char::REPLACEMENT_CHARACTER, ""))
        .filter(|word| !word.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

/// A tire's identity as TTC writes it in a MAT-file's `tireid`: `NAME, 7 inch rim`.
pub(crate) fn tire_identity(name: &str, rim: Option<&str>) -> Option<String> {
    let name = collapse(name);
    if name.is_empty() {
        return None;
    }
    Some(match rim.map(str::trim).filter(|r| !r.is_empty()) {
        None => name,
        Some(r) => match r.parse::<f64>() {
            Ok(w) if w.is_finite() => format!("{name}, {w} inch rim"),
            _ => format!("{name}, rim {r}"),
        },
    })
}

/// The key two tire names are compared by: case, commas, brackets and runs of blanks ignored,
/// a maker's item number (a word of five or more digits, with an `Item` before it) left out,
/// and a whole number written with decimals (`18.0X6.0-10`) as a whole number (`18x6-10`):
/// the `tireid` of a MAT-file and the `Tire_Name` of the same run's ASCII file spell one tire
/// so (`Hoosier 43100 18.0x6.0-10 R20` and `Hoosier 18.0X6.0-10, R20`).
pub(crate) fn tire_key(tire: &str) -> String {
    let spaced: String = tire
        .chars()
        .map(|c| match c {
            ',' | ';' | '(' | ')' => ' ',
            c => c.to_ascii_lowercase(),
        })
        .collect();
    spaced
        .split_whitespace()
        .filter(|w| *w != "item" && !(w.len() >= 5 && w.bytes().all(|b| b.is_ascii_digit())))
        .map(whole_numbers)
        .collect::<Vec<_>>()
        .join(" ")
}

/// `word` with each `.0` (or `.00`, ...) after a digit and not before another digit left out.
fn whole_numbers(word: &str) -> String {
    let b = word.as_bytes();
    let mut out = String::new();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'.' && i > 0 && b[i - 1].is_ascii_digit() {
            let zeros = b[i + 1..].iter().take_while(|&&c| c == b'0').count();
            let after = b.get(i + 1 + zeros);
            if zeros > 0 && !after.is_some_and(u8::is_ascii_digit) {
                i += 1 + zeros;
                continue;
            }
        }
        out.push(b[i] as char);
        i += 1;
    }
    out
}

/// The fields of a Calspan header title (`TIRF Data File: Project 1965; Run 051; Date ...;
/// Time ...; ISO False; ID 3Scoi1N`), by their first word: they name the test, not the tire.
const HEADER_FIELDS: [&str; 7] = ["tirf", "project", "run", "date", "time", "iso", "id"];

/// A free-text title without the Calspan header's fields (see [`HEADER_FIELDS`]).
fn without_header_fields(title: &str) -> String {
    title
        .split(';')
        .filter(|field| {
            let first = field.split_whitespace().next().unwrap_or("");
            let first = first.trim_end_matches(':').to_ascii_lowercase();
            !HEADER_FIELDS.contains(&first.as_str())
        })
        .collect::<Vec<_>>()
        .join(";")
}

/// What a run file's title says.
#[derive(Debug, Default, PartialEq)]
struct Title {
    tire: Option<String>,
    run: Option<i64>,
    /// A `Coordinate_System=` value, if the title has one.
    axes: Option<String>,
}

/// Reads a title: `Key=value; ...` fields (`Tire_Name`, `Rim_Width`, `Coordinate_System`;
/// any other text such as `Run 071` gives the run), or free text (see the module doc).
fn parse_title(title: &str) -> Title {
    let title = title.trim().trim_start_matches('\u{feff}').trim();
    if title.contains('=') {
        let mut t = Title::default();
        let (mut name, mut rim, mut rest) = (None, None, String::new());
        for part in title.split(';') {
            match part.split_once('=') {
                Some((k, v)) if k.trim().eq_ignore_ascii_case("tire_name") => name = Some(v),
                Some((k, v)) if k.trim().eq_ignore_ascii_case("rim_width") => rim = Some(v),
                Some((k, v)) if k.trim().eq_ignore_ascii_case("coordinate_system") => {
                    t.axes = Some(v.trim().to_string());
                }
                _ => {
                    rest.push_str(part);
                    rest.push(';');
                }
            }
        }
        t.run = run_number(&rest);
        t.tire = name.and_then(|n| tire_identity(n, rim));
        return t;
    }
    // Free text, maybe "Data from NAME.mat ...": then NAME is the candidate.
    let lower = title.to_ascii_lowercase();
    let candidate = match lower.strip_prefix("data from") {
        Some(rest) => {
            let start = title.len() - rest.len();
            let end = rest.find(".mat").map_or(title.len(), |k| start + k);
            &title[start..end]
        }
        None => title,
    };
    let name = collapse(&strip_run(&without_header_fields(candidate)));
    let name = name.trim_matches(|c: char| matches!(c, ' ' | '_' | '-' | ',' | ';' | '.' | ':'));
    let generic = name.is_empty() || is_programme_code(name) || name.parse::<f64>().is_ok();
    Title {
        tire: if generic {
            None
        } else {
            tire_identity(name, None)
        },
        run: run_number(title),
        axes: None,
    }
}

/// The run id of a file: from its file name, else from `text` (its title or `source`).
pub(crate) fn run_id(source: &str, text: Option<i64>) -> Option<i64> {
    let stem = Path::new(source)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("");
    run_number(stem).or(text)
}

/// A TTC run's channels, whatever the file format.
pub(crate) struct Header {
    pub names: Vec<String>,
    /// One unit per channel, as written in the file.
    pub units: Vec<String>,
    /// The file line of the units (ASCII); `None` when they come from a MAT-file.
    pub unit_line: Option<usize>,
}

/// The raw channel values a reader hands [`read_channels`]: one column per channel asked
/// for, in file units, and the file line (ASCII) or sample number (MAT) of each sample.
pub(crate) struct Columns {
    pub values: Vec<Vec<f64>>,
    pub lines: Vec<usize>,
}

/// One TTC run from its channel names, units and values, for both file formats: picks the
/// channels (see the module doc), checks and applies their units, maps SAE axes to the
/// paper's, assigns the run id and checks the result. `columns` is asked once for the
/// channels used, by index into `header.names`. `notes` are the reader's own.
pub(crate) fn read_channels(
    source: &str,
    header: &Header,
    run: Option<i64>,
    mut notes: Vec<String>,
    columns: impl FnOnce(&[usize]) -> Result<Columns, InputError>,
) -> Result<Loaded, InputError> {
    let names = &header.names;
    let err = |m: String| InputError::new(source, m);
    let (used, tread_used) = pick_channels(names, &mut notes);
    let second_slip = second_slip_ratio(names, &used);
    let reads: Vec<(Quantity, usize)> = used
        .iter()
        .copied()
        .chain(tread_used.iter().map(|&i| (Quantity::Temperature, i)))
        .chain(second_slip.map(|i| (Quantity::Kappa, i)))
        .collect();
    let conversions = unit_conversions(header, &reads, source)?;
    let ignored: Vec<&str> = names
        .iter()
        .enumerate()
        .filter(|(i, _)| !reads.iter().any(|r| r.1 == *i))
        .map(|(_, n)| n.as_str())
        .collect();
    if !ignored.is_empty() {
        notes.push(format!("channels not used: {}", ignored.join(" ")));
    }

    let needed: Vec<usize> = reads.iter().map(|r| r.1).collect();
    let raw = columns(&needed)?;
    let n = raw.lines.len();
    if raw.values.len() != needed.len() || raw.values.iter().any(|c| c.len() != n) {
        return Err(err(
            "the channels read have different numbers of samples".to_string()
        ));
    }
    let (mut raw, mut conversions) = (raw, conversions);
    let second = second_slip.map(|i| {
        let values = raw.values.pop().unwrap_or_default();
        let c = conversions.pop().expect("a conversion per channel read");
        (
            names[i].clone(),
            values.iter().map(|&v| c.apply(v)).collect(),
        )
    });
    let mut tbl = converted_table(raw, names, &used, &tread_used, &conversions);
    sae_to_paper_axes(&mut tbl, &mut notes);
    choose_slip_ratio(&mut tbl, second, &mut notes);

    // One file is one run here; the programme is split into its blocks after reading.
    if run.is_none() {
        notes.push("no run number in the file name or title: run 1".to_string());
    }
    tbl.run = Some(("file".to_string(), vec![run.unwrap_or(1); n]));
    let dataset = table::finish(source, tbl, &SPELLING, &mut notes)?;
    Ok(Loaded {
        dataset,
        notes,
        sources: Vec::new(),
    })
}

/// The channels read, as `(quantity, index into names)` by [`CHANNELS`], and the tread
/// temperature channels (all three, or TSTC alone); notes the choices made.
fn pick_channels(
    names: &[String],
    notes: &mut Vec<String>,
) -> (Vec<(Quantity, usize)>, Vec<usize>) {
    let position = |n: &str| position_of(names, n);
    let mut used: Vec<(Quantity, usize)> = Vec::new();
    for (q, candidates) in CHANNELS {
        let Some(i) = candidates.iter().find_map(|n| position(n)) else {
            continue;
        };
        used.push((*q, i));
    }
    let renamed: Vec<String> = used
        .iter()
        .filter_map(|&(q, i)| {
            let canonical = CHANNELS.iter().find(|(k, _)| *k == q)?.1;
            let name = &names[i];
            (!canonical.iter().any(|c| name.eq_ignore_ascii_case(c)))
                .then(|| format!("{name} as {}", canonical_of(name).unwrap_or("?")))
        })
        .collect();
    if !renamed.is_empty() {
        notes.push(format!(
            "channels named with a number appended read as the TTC channels: {}",
            renamed.join(", ")
        ));
    }
    let tread: Vec<Option<usize>> = TREAD.iter().map(|n| position(n)).collect();
    let tread_used: Vec<usize> = match tread.as_slice() {
        [Some(a), Some(b), Some(c)] => {
            notes.push("tread temperature: the mean of TSTI, TSTC and TSTO".to_string());
            vec![*a, *b, *c]
        }
        [_, Some(b), _] => {
            notes.push("tread temperature: TSTC (not all of TSTI, TSTC, TSTO present)".into());
            vec![*b]
        }
        _ => Vec::new(),
    };
    (used, tread_used)
}

/// `SL` when `SR` is read and the file has both: the two are compared once read.
fn second_slip_ratio(names: &[String], used: &[(Quantity, usize)]) -> Option<usize> {
    let (_, sr) = used.iter().find(|(q, _)| *q == Quantity::Kappa)?;
    (!names_channel(&names[*sr], "SL"))
        .then(|| position_of(names, "SL"))
        .flatten()
}

/// A free-rolling row: rolling (1 m/s or faster, when speed is known), loaded (a quarter of
/// the median load or more), at a slip angle below this [rad] and a longitudinal force
/// below [`FREE_ROLLING_FX`] times the load.
const FREE_ROLLING_ALPHA: f64 = 0.0175;
const FREE_ROLLING_FX: f64 = 0.05;
/// Two slip ratios whose free-rolling readings differ by less than this are alike: `SR`
/// (the effective rolling radius, SAE J670's slip ratio) is kept.
const SLIP_RATIO_ALIKE: f64 = 0.002;

/// A second slip ratio whose 99th percentile of |kappa| on the rolling, loaded rows is below
/// this share of the first's is a dead channel (e.g. `SL` saved as zeros), not a reading of
/// the slip...
const SLIP_RATIO_DEAD_SHARE: f64 = 0.1;
/// ...when the first is swept as in a drive/brake test: on at least this share of the
/// rolling, loaded rows it reads [`SLIP_RATIO_SWEPT`] or more away from its free-rolling
/// reading. In a cornering run `SR` only wanders a few percent with the slip angle (and
/// `SL`, zero, is the slip ratio the rig held).
const SLIP_RATIO_SWEPT_SHARE: f64 = 0.01;
const SLIP_RATIO_SWEPT: f64 = 0.1;

/// The rolling (1 m/s or faster, when speed is known) and loaded (a quarter of the median
/// load or more) rows.
fn rolling_loaded(tbl: &Table) -> Option<Vec<usize>> {
    let fz = &tbl.column(Quantity::Fz)?.values;
    let speed = tbl.column(Quantity::Speed).map(|c| &c.values);
    let load = median(fz)?;
    Some(
        (0..fz.len())
            .filter(|&i| fz[i] >= 0.25 * load && speed.is_none_or(|v| v[i] >= 1.0))
            .collect(),
    )
}

/// The 99th percentile of |kappa| over `rows`.
fn slip_ratio_reach(kappa: &[f64], rows: &[usize]) -> Option<f64> {
    let magnitudes: Vec<f64> = rows.iter().map(|&i| kappa[i].abs()).collect();
    quantile(&magnitudes, 0.99)
}

/// The share of `rows` on which `kappa` reads [`SLIP_RATIO_SWEPT`] or more from `free`.
fn swept_share(kappa: &[f64], rows: &[usize], free: f64) -> f64 {
    let swept = rows
        .iter()
        .filter(|&&i| (kappa[i] - free).abs() >= SLIP_RATIO_SWEPT)
        .count();
    swept as f64 / rows.len().max(1) as f64
}

/// The median reading of a slip ratio `kappa` on the free-rolling rows among `rows` (the
/// rolling, loaded ones), with their number.
fn free_rolling_reading(tbl: &Table, rows: &[usize], kappa: &[f64]) -> Option<(f64, usize)> {
    let fz = &tbl.column(Quantity::Fz)?.values;
    let fx = &tbl.column(Quantity::Fx)?.values;
    let alpha = tbl.column(Quantity::Alpha).map(|c| &c.values);
    let free: Vec<f64> = rows
        .iter()
        .filter(|&&i| {
            fx[i].abs() < FREE_ROLLING_FX * fz[i]
                && alpha.is_none_or(|a| a[i].abs() < FREE_ROLLING_ALPHA)
                && kappa[i].abs() < 0.5
        })
        .map(|&i| kappa[i])
        .collect();
    Some((median(&free)?, free.len()))
}

/// The slip ratio read, noted: `SR`, or `SL` alone, or of both the one that reads zero where
/// the tire rolls freely (the other's offset would be fitted as a shift of the curve).
fn choose_slip_ratio(tbl: &mut Table, second: Option<(String, Vec<f64>)>, notes: &mut Vec<String>) {
    let Some(read) = tbl.column(Quantity::Kappa).map(|c| c.label.clone()) else {
        return;
    };
    let Some((other, values)) = second else {
        notes.push(if names_channel(&read, "SL") {
            format!("slip ratio read from {read} (loaded radius): there is no SR channel")
        } else {
            format!("slip ratio read from {read} (effective rolling radius)")
        });
        return;
    };
    let rows = rolling_loaded(tbl).unwrap_or_default();
    let kappa = tbl.column(Quantity::Kappa).map(|c| &c.values[..]);
    let sr = kappa.and_then(|k| free_rolling_reading(tbl, &rows, k));
    let sl = free_rolling_reading(tbl, &rows, &values);
    let reach = kappa.and_then(|k| slip_ratio_reach(k, &rows));
    if let (Some(k), Some(read_reach), Some(other_reach), Some((free, _))) =
        (kappa, reach, slip_ratio_reach(&values, &rows), sr)
        && other_reach < SLIP_RATIO_DEAD_SHARE * read_reach
        && swept_share(k, &rows, free) >= SLIP_RATIO_SWEPT_SHARE
    {
        notes.push(format!(
            "slip ratio read from {read} (effective rolling radius); {other} (loaded radius) not \
             used: it barely varies where {read} is swept (99th percentile of |{other}| \
             {other_reach:.4}, of |{read}| {read_reach:.4}, on the rolling, loaded rows)"
        ));
        return;
    }
    let (Some((at_sr, rows)), Some((at_sl, _))) = (sr, sl) else {
        notes.push(format!(
            "slip ratio read from {read} (effective rolling radius); {other} (loaded radius) \
             not used: no free-rolling rows (|Fx| < {FREE_ROLLING_FX} Fz, |alpha| < 1 deg) to \
             compare them on"
        ));
        return;
    };
    let compared = format!(
        "at free rolling (|Fx| < {FREE_ROLLING_FX} Fz, |alpha| < 1 deg; {rows} rows) {read} \
         reads {at_sr:+.4} and {other} {at_sl:+.4}"
    );
    if at_sl.abs() + SLIP_RATIO_ALIKE < at_sr.abs() {
        if let Some(col) = tbl.column_mut(Quantity::Kappa) {
            col.values = values;
            col.label = other.clone();
        }
        notes.push(format!(
            "slip ratio read from {other} (loaded radius), not {read}: {compared}; the slip \
             ratio that reads zero where the tire rolls freely is taken"
        ));
    } else {
        notes.push(format!(
            "slip ratio read from {read} (effective rolling radius), not {other}: {compared}"
        ));
    }
}

/// The conversion of each channel read from its unit to internal units; an unaccepted
/// unit is an error naming the channel (and the units line of an ASCII file).
fn unit_conversions(
    header: &Header,
    reads: &[(Quantity, usize)],
    source: &str,
) -> Result<Vec<units::Conversion>, InputError> {
    reads
        .iter()
        .map(|&(q, i)| {
            let unit = header.units.get(i).map_or("", String::as_str);
            units::conversion(q, unit).ok_or_else(|| {
                let from = match header.unit_line {
                    Some(_) => "",
                    None => " (channel.units)",
                };
                let e = InputError::new(
                    source,
                    format!(
                        "unit \"{unit}\"{from} is not accepted for {} (accepted: {})",
                        q.name(),
                        units::accepted_list(q)
                    ),
                )
                .in_column(&header.names[i]);
                match header.unit_line {
                    Some(line) => e.at_line(line),
                    None => e,
                }
            })
        })
        .collect()
}

/// The table of the channels read in internal units, slip angle in the paper's sign, and
/// the tread temperature as the mean of its channels. `conversions` are those of `used`
/// then of `tread_used`, as are the columns of `raw`.
fn converted_table(
    raw: Columns,
    names: &[String],
    used: &[(Quantity, usize)],
    tread_used: &[usize],
    conversions: &[units::Conversion],
) -> Table {
    let n = raw.lines.len();
    let mut tbl = Table {
        lines: raw.lines,
        ..Table::default()
    };
    for (k, &(q, i)) in used.iter().enumerate() {
        let c = conversions[k];
        let values = raw.values[k]
            .iter()
            .map(|&v| sae_to_paper(q) * c.apply(v))
            .collect();
        tbl.columns.push((
            q,
            table::Column {
                label: names[i].clone(),
                values,
            },
        ));
    }
    if !tread_used.is_empty() {
        let first = used.len();
        let values = (0..n)
            .map(|row| {
                let sum: f64 = (first..conversions.len())
                    .map(|k| conversions[k].apply(raw.values[k][row]))
                    .sum();
                sum / tread_used.len() as f64
            })
            .collect();
        let label = tread_used
            .iter()
            .map(|&i| names[i].as_str())
            .collect::<Vec<_>>()
            .join("+");
        tbl.columns
            .push((Quantity::Temperature, table::Column { label, values }));
    }
    tbl
}

/// SAE to the paper's axes: the slip angle was negated when converted; the load is made
/// positive (noted).
fn sae_to_paper_axes(tbl: &mut Table, notes: &mut Vec<String>) {
    notes.push(
        "TTC axes are SAE (x forward, y right, z down); converted to the paper's axes: \
         alpha = -SA (a positive SAE slip angle gives a negative lateral force), Fz = -FZ; \
         camber, slip ratio, Fx, Fy and Mz keep their sign"
            .to_string(),
    );
    if let Some(col) = tbl.column_mut(Quantity::Fz) {
        if median(&col.values).is_some_and(|m| m < 0.0) {
            col.values.iter_mut().for_each(|v| *v = -*v);
        } else {
            notes.push("FZ is mostly positive: taken as the load as it is (not negated)".into());
        }
    }
}

/// Reads a TTC ASCII run file held in memory; `source` names it (its file name gives the run
/// id).
pub fn read_str(text: &str, source: &str) -> Result<Loaded, InputError> {
    read_run(text, source).map(|(loaded, _)| loaded)
}

/// Reads a TTC ASCII run file held in memory, with the tire its title names.
pub(crate) fn read_run(text: &str, source: &str) -> Result<(Loaded, Option<String>), InputError> {
    let err = |m: String| InputError::new(source, m);
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_start_matches('\u{feff}')))
        .filter(|(_, l)| !l.trim().is_empty());
    let (title_line, title) = lines
        .next()
        .ok_or_else(|| err("the file is empty".into()))?;
    let (names_line, names) = lines
        .next()
        .ok_or_else(|| err("no channel-name line (line 2 of a TTC run file)".into()))?;
    let (units_line, unit_text) = lines
        .next()
        .ok_or_else(|| err("no unit line (line 3 of a TTC run file)".into()))?;
    let names = channel_names(names).map_err(|m| err(m).at_line(names_line))?;
    let units = unit_entries(unit_text, &names).map_err(|m| err(m).at_line(units_line))?;
    let title = parse_title(title);
    if let Some(axes) = &title.axes
        && !axes.eq_ignore_ascii_case("sae")
    {
        return Err(err(format!(
            "the title gives Coordinate_System={axes}: tire-gap reads TTC data in SAE axes only"
        ))
        .at_line(title_line));
    }
    let mut notes = Vec::new();
    if let Some(tire) = &title.tire {
        notes.push(format!("tire: {tire}"));
    }
    let header = Header {
        names,
        units,
        unit_line: Some(units_line),
    };
    let count = header.names.len();
    let loaded = read_channels(
        source,
        &header,
        run_id(source, title.run),
        notes,
        |needed| {
            let mut out = Columns {
                values: vec![Vec::new(); needed.len()],
                lines: Vec::new(),
            };
            let mut row: Vec<&str> = Vec::with_capacity(count);
            for (line, text) in lines {
                row.clear();
                row.extend(text.split_whitespace());
                if row.len() != count {
                    return Err(err(format!(
                        "{} values for {count} channels (line {names_line} names them)",
                        row.len(),
                    ))
                    .at_line(line));
                }
                for (k, &i) in needed.iter().enumerate() {
                    let v = table::parse_number(row[i])
                        .map_err(|m| err(m).at_line(line).in_column(&header.names[i]))?;
                    out.values[k].push(v);
                }
                out.lines.push(line);
            }
            Ok(out)
        },
    )?;
    Ok((loaded, title.tire))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(s: &str) -> Vec<String> {
        channel_names(s).unwrap()
    }

    #[test]
    fn run_numbers_come_from_the_name_or_the_title() {
        assert_eq!(run_number("B1464run23"), Some(23));
        assert_eq!(run_number("b1654_RUN_7"), Some(7));
        assert_eq!(run_number("Data from B1464run4.mat"), Some(4));
        assert_eq!(run_number("Run 071"), Some(71));
        assert_eq!(run_number("cornering"), None);
        assert_eq!(run_number("runway"), None);
    }

    #[test]
    fn detection_needs_load_slip_and_a_unit_per_channel() {
        let good = "title\nET FZ SA FY\ns N deg N\n0 -1000 1 -100\n";
        assert!(looks_like(good));
        assert!(looks_like("t\nET\tFZ\tSA\tRST\ns\tN\tdeg\tdeg c\n"));
        assert!(!looks_like("title\nET FZ FY\ns N N\n"));
        assert!(!looks_like("title\nET FZ SA FY\ns N deg\n"));
        assert!(!looks_like("run,fz_N,alpha_deg\n1,2,3\n"));
    }

    #[test]
    fn unit_lines_split_at_tabs_or_into_known_units() {
        let n = names("ET\tSA\tRST\tTSTC\tSR");
        assert_eq!(
            unit_entries("s\tdeg\tdeg c\tdeg c\tSAE\t\r", &n).unwrap(),
            ["s", "deg", "deg c", "deg c", "SAE"]
        );
        // The same line with blanks: two-word units are grouped.
        assert_eq!(
            unit_entries("s deg deg c deg c SAE", &n).unwrap(),
            ["s", "deg", "deg c", "deg c", "SAE"]
        );
        // "N m" is a unit, but here it must be split to give every channel one.
        let n = names("FZ RL FY");
        assert_eq!(unit_entries("N m N", &n).unwrap(), ["N", "m", "N"]);
        // One word per channel when the words are as many as the channels.
        let n = names("FZ SA");
        assert_eq!(unit_entries("N furlong", &n).unwrap(), ["N", "furlong"]);
        let e = unit_entries("N furlong deg C", &names("FZ SA RST")).unwrap_err();
        assert!(
            e.contains("\"furlong\" (word 2) is not a known unit")
                && e.contains("channel SA (entry 2)"),
            "{e}"
        );
        let e = unit_entries("N deg", &names("FZ SA FY")).unwrap_err();
        assert!(e.contains("gives 2 units for 3 channels"), "{e}");
        // A huge header neither recurses deeply nor builds a huge table.
        let many = vec!["X"; 200_000].join(" ");
        let n = names(&many);
        let line = vec!["deg C"; 200_000].join(" ");
        assert_eq!(unit_entries(&line, &n).unwrap()[199_999], "deg C");
    }

    #[test]
    fn titles_give_tire_run_and_axes() {
        let t = parse_title("Tire_Name=Hoosier 43075 16x7.5-10 R25B; Rim_Width=7; Run 071");
        assert_eq!(
            t.tire.as_deref(),
            Some("Hoosier 43075 16x7.5-10 R25B, 7 inch rim")
        );
        assert_eq!(t.run, Some(71));
        let t = parse_title("Tire_Name=Avon run5 special; Coordinate_System=SAE");
        assert_eq!(
            (t.tire.as_deref(), t.run, t.axes.as_deref()),
            (Some("Avon run5 special"), None, Some("SAE"))
        );
        let t = parse_title("Hoosier R25B 18.0x6.0-10 Run 12");
        assert_eq!(t.tire.as_deref(), Some("Hoosier R25B 18.0x6.0-10"));
        assert_eq!(t.run, Some(12));
        let t = parse_title("Data from Goodyear D2704 run3.mat");
        assert_eq!(t.tire.as_deref(), Some("Goodyear D2704"));
        for generic in [
            "Data from B1464run23.mat",
            "Data from B1654run5.mat (US units)",
            "Data from run2",
            "\u{feff}Data from B9run4.mat",
            "run 7",
            "",
            "TIRF Data File: Project 1654; Run 34",
            "TIRF Data File: Project 1965; Run 051; Date 08-01-2018; Time 19:19; ISO False; ID 3Scoi1N",
        ] {
            assert_eq!(parse_title(generic).tire, None, "{generic}");
        }
    }

    #[test]
    fn tire_names_compare_ignoring_case_and_blanks() {
        assert_eq!(
            tire_key("Hoosier  R25B ,  7 inch rim"),
            tire_key("hoosier r25b 7 inch rim")
        );
        assert_ne!(tire_key("Hoosier R25B"), tire_key("Hoosier R20"));
        // A MAT-file's tireid and the same run's Tire_Name and Rim_Width.
        assert_eq!(
            tire_key("Hoosier 43100 18.0x6.0-10 R20, 7 inch rim"),
            tire_key(&tire_identity("Hoosier 18.0X6.0-10, R20", Some("7.0")).unwrap())
        );
        assert_eq!(tire_key("R25B (Item 43105)"), tire_key("r25b"));
        assert_ne!(
            tire_key("Hoosier 18.0x6.0-10"),
            tire_key("Hoosier 18.0x7.5-10")
        );
        assert_ne!(tire_key("Avon 7.05 mix"), tire_key("Avon 7 mix"));
        assert_eq!(tire_identity(" ", Some("7")), None);
        // An undecodable character (one encoding gives U+FFFD, another drops it) is left out.
        assert_eq!(
            tire_identity("R25B\u{FFFD} (Item 43105), 7 inch rim", None),
            tire_identity("R25B (Item 43105), 7 inch rim", None)
        );
        assert_eq!(tire_identity("\u{FFFD}", None), None);
        assert_eq!(
            tire_identity("X", Some("6.5")).as_deref(),
            Some("X, 6.5 inch rim")
        );
        assert_eq!(strip_run("B1464run23"), "B1464");
        assert_eq!(strip_run("a Run 071 b"), "a  b");
        assert_eq!(strip_run("Brunswick run_4"), "Brunswick ");
    }
}
