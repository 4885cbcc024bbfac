//! `acs attitude`: optimal attitude from vector pairs (JSON in, JSON out; `docs/cli.md`).
//!
//! stdin: `{"body": [[x,y,z],...], "reference": [[x,y,z],...], "weights": [w,...]}` (blank lines
//! and lines starting with `#` ignored; `weights` may be omitted for equal weights). The vectors
//! are normalised; weights must be > 0. stdout:
//! `{"dcm": [[...],[...],[...]], "quaternion": [q0,q1,q2,q3]}` with `v_body = dcm · v_ref` and
//! the scalar-first quaternion of the same rotation ([`crate::attitude`]), numbers with 10
//! significant digits. The solvers are the f32 flight code: `svd` (default, Wahba by SVD),
//! `quest`, `triad` (first two vectors).
//!
//! Exit 2: malformed JSON, a missing or mistyped field, vectors not of 3 numbers, lengths that
//! do not match, zero vectors, weights ≤ 0, numbers beyond f32. Exit 3: degenerate geometry
//! (fewer than two vectors, all directions parallel).

use std::io::Read;

use serde_json::Value;

use crate::determination::{quest, triad, wahba_svd, DeterminationError, Observation, Solution};
use crate::linalg::Vec3;

use super::CliError;

/// Arguments of `acs attitude`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Solver.
    #[arg(long, value_parser = ["svd", "quest", "triad"], default_value = "svd")]
    method: String,
}

/// A JSON number as f32, refusing values beyond the f32 range.
fn number(v: &Value, field: &str) -> Result<f32, CliError> {
    let x = v
        .as_f64()
        .ok_or_else(|| CliError::Input(format!("`{field}` is not a number: {v}")))?;
    let y = x as f32;
    if !y.is_finite() {
        return Err(CliError::Input(format!(
            "`{field}` = {x} is beyond the f32 range"
        )));
    }
    Ok(y)
}

/// The array of 3-vectors in `doc[name]`.
fn vectors(doc: &Value, name: &str) -> Result<Vec<Vec3>, CliError> {
    let arr = doc
        .get(name)
        .ok_or_else(|| CliError::Input(format!("missing field `{name}`")))?
        .as_array()
        .ok_or_else(|| CliError::Input(format!("`{name}` is not an array")))?;
    arr.iter()
        .enumerate()
        .map(|(i, v)| {
            let field = format!("{name}[{i}]");
            match v.as_array().map(Vec::as_slice) {
                Some([x, y, z]) => Ok(Vec3::new(
                    number(x, &format!("{field}[0]"))?,
                    number(y, &format!("{field}[1]"))?,
                    number(z, &format!("{field}[2]"))?,
                )),
                _ => Err(CliError::Input(format!(
                    "`{field}` is not an array of 3 numbers: {v}"
                ))),
            }
        })
        .collect()
}

/// Parses the input document into observations (public for the fuzz target `cli_attitude`).
pub fn parse(text: &str) -> Result<Vec<Observation>, CliError> {
    // Blank lines and `#` comment lines are ignored (cli.md, general rules).
    let json: String = text
        .lines()
        .filter(|l| {
            let t = l.trim_start();
            !t.is_empty() && !t.starts_with('#')
        })
        .collect::<Vec<_>>()
        .join("\n");
    let doc: Value = serde_json::from_str(&json).map_err(|e| {
        CliError::Input(format!(
            "malformed JSON at line {}, column {} (comment lines not counted): {e}",
            e.line(),
            e.column()
        ))
    })?;
    if !doc.is_object() {
        return Err(CliError::Input("the input is not a JSON object".into()));
    }
    let body = vectors(&doc, "body")?;
    let reference = vectors(&doc, "reference")?;
    if body.len() != reference.len() {
        return Err(CliError::Input(format!(
            "`body` has {} vectors but `reference` {}",
            body.len(),
            reference.len()
        )));
    }
    let weights: Vec<f32> = match doc.get("weights") {
        None | Some(Value::Null) => vec![1.0; body.len()],
        Some(w) => {
            let arr = w
                .as_array()
                .ok_or_else(|| CliError::Input("`weights` is not an array".into()))?;
            arr.iter()
                .enumerate()
                .map(|(i, x)| number(x, &format!("weights[{i}]")))
                .collect::<Result<_, _>>()?
        }
    };
    if weights.len() != body.len() {
        return Err(CliError::Input(format!(
            "`weights` has {} entries but there are {} vector pairs",
            weights.len(),
            body.len()
        )));
    }
    Ok(body
        .into_iter()
        .zip(reference)
        .zip(weights)
        .map(|((body, reference), weight)| Observation {
            body,
            reference,
            weight,
        })
        .collect())
}

/// Maps a solver error to the exit code: bad values are input errors (2), geometry is a
/// computation failure (3).
fn map_error(e: DeterminationError) -> CliError {
    match e {
        DeterminationError::NonFinite { .. }
        | DeterminationError::ZeroVector { .. }
        | DeterminationError::BadWeight { .. }
        | DeterminationError::LengthMismatch { .. } => CliError::Input(e.to_string()),
        _ => CliError::Compute(format!("degenerate geometry: {e}")),
    }
}

/// The output document, numbers with 10 significant digits.
fn render(s: &Solution) -> String {
    let m = s.dcm.matrix();
    let f = |x: f32| format!("{:.9e}", f64::from(x));
    let row = |a: f32, b: f32, c: f32| format!("[{}, {}, {}]", f(a), f(b), f(c));
    let q = &s.quaternion;
    format!(
        "{{\"dcm\": [{}, {}, {}], \"quaternion\": [{}, {}, {}, {}]}}",
        row(m.m11, m.m12, m.m13),
        row(m.m21, m.m22, m.m23),
        row(m.m31, m.m32, m.m33),
        f(q.q0),
        f(q.q1),
        f(q.q2),
        f(q.q3)
    )
}

/// Solves one input document with `method` (`svd`, `quest`, `triad`): what `acs attitude`
/// prints for stdin `text` (public for the fuzz target `cli_attitude`).
pub fn solve_text(text: &str, method: &str) -> Result<String, CliError> {
    let obs = parse(text)?;
    let solution = match method {
        "quest" => quest::solve(&obs),
        "triad" => triad::solve(&obs),
        _ => wahba_svd::solve(&obs),
    }
    .map_err(map_error)?;
    Ok(render(&solution))
}

/// Runs `acs attitude`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let mut text = String::new();
    std::io::stdin()
        .read_to_string(&mut text)
        .map_err(|e| CliError::Input(format!("cannot read stdin: {e}")))?;
    println!("{}", solve_text(&text, &args.method)?);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_and_refuses() {
        let input = "# two vectors\n{\"body\": [[0,1,0],[0,0,1]], \"reference\": [[1,0,0],[0,1,0]], \"weights\": [1, 1]}\n";
        for m in ["svd", "quest", "triad"] {
            let out = solve_text(input, m).unwrap();
            let v: Value = serde_json::from_str(&out).unwrap();
            // A maps x → y, y → z: rows of A are (0,0,1), (1,0,0), (0,1,0).
            let a: Vec<Vec<f64>> = serde_json::from_value(v["dcm"].clone()).unwrap();
            let expected = [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
            for (r, e) in a.iter().zip(expected.iter()) {
                for (x, y) in r.iter().zip(e.iter()) {
                    assert!((x - y).abs() < 1e-6, "{m}: {out}");
                }
            }
            let q: Vec<f64> = serde_json::from_value(v["quaternion"].clone()).unwrap();
            assert!((q[0] - 0.5).abs() < 1e-6 && q.iter().all(|x| (x.abs() - 0.5).abs() < 1e-6));
        }
        let code = |s: &str| solve_text(s, "svd").unwrap_err().exit_code();
        assert_eq!(code("{"), 2);
        assert_eq!(code("[]"), 2);
        assert_eq!(code("{\"body\": [[1,0,0]], \"reference\": []}"), 2);
        assert_eq!(
            code(
                "{\"body\": [[1,0,0],[0,1,0]], \"reference\": [[1,0,0],[0,1,0]], \"weights\": [1]}"
            ),
            2
        );
        assert_eq!(code("{\"body\": [[1,0]], \"reference\": [[1,0,0]]}"), 2);
        assert_eq!(
            code("{\"body\": [[1,0,\"x\"]], \"reference\": [[1,0,0]]}"),
            2
        );
        assert_eq!(
            code("{\"body\": [[1,0,0],[0,1,0]], \"reference\": [[1,0,0],[0,1,0]], \"weights\": [1, 0]}"),
            2
        );
        assert_eq!(
            code("{\"body\": [[1e39,0,0],[0,1,0]], \"reference\": [[1,0,0],[0,1,0]]}"),
            2
        );
        assert_eq!(code("{\"body\": [[1,0,0]], \"reference\": [[0,1,0]]}"), 3);
        assert_eq!(
            code("{\"body\": [[1,0,0],[2,0,0]], \"reference\": [[0,1,0],[0,3,0]]}"),
            3
        );
    }
}
