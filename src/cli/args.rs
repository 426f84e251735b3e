//! The value parsers of the subcommands' options and the values they give.

pub(super) fn parse_size_at(s: &str) -> Result<(f64, f64, f64), String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| "a point size is X,Y,H (three numbers)".to_string())?;
    match v[..] {
        [x, y, h] if x.is_finite() && y.is_finite() && h.is_finite() && h > 0.0 => Ok((x, y, h)),
        _ => Err("a point size is X,Y,H with H a positive number".into()),
    }
}

pub(super) fn parse_size_on(s: &str) -> Result<(String, f64), String> {
    let (layer, h) = s.rsplit_once('=').ok_or("a layer size is LAYER=H")?;
    match h.trim().parse::<f64>() {
        Ok(h) if h.is_finite() && h > 0.0 => Ok((layer.to_string(), h)),
        _ => Err("a layer size is LAYER=H with H a positive number".into()),
    }
}

#[cfg(feature = "gui")]
pub(super) fn parse_size(s: &str) -> Result<[f32; 2], String> {
    let (w, h) = s.split_once('x').ok_or("size is WIDTHxHEIGHT")?;
    match (w.parse::<f32>(), h.parse::<f32>()) {
        (Ok(w), Ok(h)) if w >= 200.0 && h >= 200.0 => Ok([w, h]),
        _ => Err("size is WIDTHxHEIGHT, each at least 200".into()),
    }
}

/// `--layers`: a count, or `all` for extraction to the end.
#[derive(Clone, Copy, Debug)]
pub(super) struct Layers(pub(super) Option<u32>);

pub(super) fn parse_remesh_below(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err(format!(
            "`{s}` is not a scaled Jacobian from 0 (no remeshing) to 1"
        )),
    }
}

pub(super) fn parse_layers(s: &str) -> Result<Layers, String> {
    if s == "all" {
        return Ok(Layers(None));
    }
    match s.parse::<u32>() {
        Ok(k) if k >= 1 => Ok(Layers(Some(k))),
        _ => Err(format!("`{s}` is not a layer count (1 or more) or `all`")),
    }
}

/// `--transitions`: a ratio above 1, or `off`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Transitions(pub(super) Option<f64>);

pub(super) fn parse_transitions(s: &str) -> Result<Transitions, String> {
    off_or(s, |r: &f64| *r > 1.0 && r.is_finite(), "a ratio above 1").map(Transitions)
}

/// A value `keep` accepts, or `off` (`None`); `what` names the value in
/// the error.
fn off_or<T: std::str::FromStr>(
    s: &str,
    keep: impl Fn(&T) -> bool,
    what: &str,
) -> Result<Option<T>, String> {
    if s == "off" {
        return Ok(None);
    }
    match s.parse::<T>() {
        Ok(v) if keep(&v) => Ok(Some(v)),
        _ => Err(format!("`{s}` is not {what} or `off`")),
    }
}

/// `--mapped-rows`: a count of at least 1, or `off`.
#[derive(Clone, Copy, Debug)]
pub(super) struct MappedRows(pub(super) Option<usize>);

pub(super) fn parse_mapped_rows(s: &str) -> Result<MappedRows, String> {
    off_or(s, |n: &usize| *n >= 1, "a count of at least 1").map(MappedRows)
}

pub(super) fn parse_points(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n @ (5 | 7 | 9 | 11)) => Ok(n),
        _ => Err("input points must be 5, 7, 9 or 11".into()),
    }
}
