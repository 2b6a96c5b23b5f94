//! A regression suite's report (`nearmiss test`): one case per scene file,
//! its count line, and the two formats CI systems read: JUnit XML (GitLab,
//! Jenkins, GitHub show each scene as a test case with expected, obtained
//! and error) and JSON.

use std::path::Path;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::regression::verdict;
use nearmiss::math::Real;
use nearmiss::scene::Scene;

/// How one scene fared.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CaseStatus {
    /// It met its expectation.
    Passed,
    /// It missed it.
    Failed,
    /// The scene could not be loaded (bad input).
    Bad,
    /// It states no expectation.
    Skipped,
}

/// One scene of a suite.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SuiteCase {
    /// The scene file, as given.
    pub file: String,
    /// The scene's name (`None` if it could not be loaded).
    pub scene: Option<String>,
    /// How it fared.
    pub status: CaseStatus,
    /// The expectation, in words.
    pub expected: Option<String>,
    /// What the run gave, in words.
    pub obtained: Option<String>,
    /// obtained − expected time, when both are times.
    pub error: Option<Real>,
    /// Why a bad scene is bad; for a failed one, the hint of its verdict
    /// (a tolerance tighter than the contact contract allows).
    pub message: Option<String>,
    /// Loading and running, seconds (not deterministic).
    pub wall_time_s: Real,
}

/// Loads the scene at `path` (refused if its run would take more than
/// `max_steps` steps), runs it if it states an expectation, and checks it.
pub fn run_case(path: &Path, max_steps: u64) -> SuiteCase {
    let start = Instant::now();
    let file = path.display().to_string();
    let mut case = SuiteCase {
        file,
        scene: None,
        status: CaseStatus::Bad,
        expected: None,
        obtained: None,
        error: None,
        message: None,
        wall_time_s: 0.0,
    };
    let scene = match Scene::load_within(path, max_steps) {
        Ok(scene) => scene,
        Err(error) => {
            case.message = Some(error.to_string());
            case.wall_time_s = start.elapsed().as_secs_f64();
            return case;
        }
    };
    case.scene = Some(scene.run().name.clone());
    case.status = CaseStatus::Skipped;
    if scene.run().expect.is_some() {
        let result = nearmiss::run(&scene);
        if let Some(v) = verdict(&scene, &result) {
            case.status = if v.passed { CaseStatus::Passed } else { CaseStatus::Failed };
            (case.expected, case.obtained, case.error) = (Some(v.expected), Some(v.obtained), v.error);
            case.message = v.hint;
        }
    }
    case.wall_time_s = start.elapsed().as_secs_f64();
    case
}

/// The cases with each status: (passed, failed, bad, skipped).
pub fn suite_counts(cases: &[SuiteCase]) -> (usize, usize, usize, usize) {
    let count = |status: CaseStatus| cases.iter().filter(|c| c.status == status).count();
    (count(CaseStatus::Passed), count(CaseStatus::Failed), count(CaseStatus::Bad), count(CaseStatus::Skipped))
}

/// The closing line: `N passed, M failed, K skipped` (bad scenes count as
/// failed), the form CI systems read.
pub fn count_line(cases: &[SuiteCase]) -> String {
    let (passed, failed, bad, skipped) = suite_counts(cases);
    format!("{passed} passed, {} failed, {skipped} skipped", failed + bad)
}

/// One human-readable line per case: `pass`, `FAIL`, `bad` or `skip`.
pub fn case_line(case: &SuiteCase) -> String {
    match case.status {
        CaseStatus::Skipped => format!("skip {}: states no expectation", case.file),
        CaseStatus::Bad => format!("bad {}: {}", case.file, case.message.as_deref().unwrap_or("")),
        CaseStatus::Passed | CaseStatus::Failed => {
            let error =
                case.error.map_or(String::new(), |e| format!(", error {}", crate::text::signed(e, 3)));
            let hint = case.message.as_ref().map_or(String::new(), |h| format!("\n  hint: {h}"));
            format!(
                "{} {}: expected {}; obtained {}{error}{hint}",
                if case.status == CaseStatus::Passed { "pass" } else { "FAIL" },
                case.file,
                case.expected.as_deref().unwrap_or(""),
                case.obtained.as_deref().unwrap_or("")
            )
        }
    }
}

/// The suite as JSON: the counts and every case.
pub fn suite_json(cases: &[SuiteCase]) -> String {
    #[derive(Serialize)]
    struct Suite<'a> {
        passed: usize,
        failed: usize,
        bad: usize,
        skipped: usize,
        cases: &'a [SuiteCase],
    }
    let (passed, failed, bad, skipped) = suite_counts(cases);
    // Plain structs of strings and finite numbers: serialising cannot fail.
    serde_json::to_string_pretty(&Suite { passed, failed, bad, skipped, cases }).unwrap_or_default() + "\n"
}

/// Text as XML character data or an attribute value.
fn xml_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // XML 1.0 allows no other control characters.
            c if (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r') => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}

/// The suite as JUnit XML: one `testcase` per scene file (class: its
/// folder), a `failure` with expected, obtained and error for a missed
/// expectation, an `error` for a bad scene, `skipped` without expectation.
pub fn junit_xml(cases: &[SuiteCase]) -> String {
    let (_, failed, bad, skipped) = suite_counts(cases);
    let time: Real = cases.iter().map(|c| c.wall_time_s).sum();
    let counts = format!(
        r#"tests="{}" failures="{failed}" errors="{bad}" skipped="{skipped}" time="{time:.3}""#,
        cases.len()
    );
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    out.push_str(&format!("<testsuites name=\"nearmiss test\" {counts}>\n"));
    out.push_str(&format!("  <testsuite name=\"nearmiss\" {counts}>\n"));
    for case in cases {
        let path = Path::new(&case.file);
        let class = path.parent().map(|p| p.display().to_string()).filter(|p| !p.is_empty());
        let name = path.file_name().map_or(case.file.clone(), |n| n.to_string_lossy().into_owned());
        out.push_str(&format!(
            "    <testcase classname=\"{}\" name=\"{}\" file=\"{}\" time=\"{:.3}\">\n",
            xml_escape(&class.unwrap_or_else(|| ".".into())),
            xml_escape(&name),
            xml_escape(&case.file),
            case.wall_time_s
        ));
        let details = || {
            let error =
                case.error.map_or(String::new(), |e| format!("\nerror (obtained - expected): {e:+.6e}"));
            format!(
                "expected: {}\nobtained: {}{error}",
                case.expected.as_deref().unwrap_or(""),
                case.obtained.as_deref().unwrap_or("")
            )
        };
        match case.status {
            CaseStatus::Passed => {
                out.push_str(&format!("      <system-out>{}</system-out>\n", xml_escape(&details())))
            }
            CaseStatus::Failed => out.push_str(&format!(
                "      <failure message=\"{}\" type=\"expectation\">{}</failure>\n",
                xml_escape(&format!("expected {}", case.expected.as_deref().unwrap_or(""))),
                xml_escape(&details())
            )),
            CaseStatus::Bad => out.push_str(&format!(
                "      <error message=\"bad scene\" type=\"input\">{}</error>\n",
                xml_escape(case.message.as_deref().unwrap_or(""))
            )),
            CaseStatus::Skipped => {
                out.push_str("      <skipped message=\"the scene states no expectation\"/>\n")
            }
        }
        out.push_str("    </testcase>\n");
    }
    out.push_str("  </testsuite>\n</testsuites>\n");
    out
}
