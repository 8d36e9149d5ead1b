//! The causal graph view: one variable of a why-answer's model with its
//! causes above and its effects below, joined by edges in box characters.
//! A pure function of the neighbourhood, the neighbour picked and the width.

use crate::causal::{GraphNode, Neighbourhood};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};

/// A row of cells being drawn.
type Row = Vec<(char, Style)>;

fn blank(width: usize) -> Row {
    vec![(' ', Style::default()); width]
}

fn to_line(row: Row) -> Line<'static> {
    let mut spans: Vec<Span> = Vec::new();
    let mut text = String::new();
    let mut style = None;
    for (c, st) in row {
        if style != Some(st) && !text.is_empty() {
            spans.push(Span::styled(
                std::mem::take(&mut text),
                style.unwrap_or_default(),
            ));
        }
        style = Some(st);
        text.push(c);
    }
    let trimmed = text.trim_end().to_string();
    if !trimmed.is_empty() {
        spans.push(Span::styled(trimmed, style.unwrap_or_default()));
    }
    Line::from(spans)
}

/// The most lines a label wraps to; the picked variable is told in full
/// below the graph.
const LABEL_LINES: usize = 3;

/// `[name = value]` with its marks: `★` a reason of the picked explanation,
/// `◎` the variable asked about; wrapped to `max` columns, at most
/// `LABEL_LINES` lines (the last cut with `…` past them).
fn label(n: &GraphNode, max: usize) -> Vec<String> {
    let mark = match (n.target, n.reason) {
        (true, _) => "◎",
        (_, true) => "★",
        _ => "",
    };
    let inner = format!("{mark}{} = {}", n.name, n.value);
    let width = max.saturating_sub(2).max(1);
    let mut lines: Vec<String> = textwrap::wrap(&inner, width)
        .into_iter()
        .map(|l| l.into_owned())
        .collect();
    if lines.len() > LABEL_LINES {
        let rest = lines[LABEL_LINES - 1..].join(" ");
        lines.truncate(LABEL_LINES - 1);
        lines.push(super::view::fit(&rest, width));
    }
    let last = lines.len() - 1;
    lines
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let open = if i == 0 { '[' } else { ' ' };
            let close = if i == last { "]" } else { "" };
            format!("{open}{l}{close}")
        })
        .collect()
}

fn style(n: &GraphNode, picked: bool) -> Style {
    let mut st = if n.reason {
        Style::default()
            .fg(Color::Yellow)
            .add_modifier(Modifier::BOLD)
    } else if n.target {
        Style::default().add_modifier(Modifier::BOLD)
    } else {
        Style::default()
    };
    if picked {
        st = st.add_modifier(Modifier::REVERSED);
    }
    st
}

/// Lays out a row of labels: a window of them around `pick` that fits the
/// width, centred, each wrapped to its share of it; labels of fewer lines
/// sit against the edges (`bottom`: the edges leave from below). Returns
/// the rows, each shown label's anchor column (its middle), and how many
/// are left out to the left and right.
fn row_of(
    nodes: &[GraphNode],
    pick: Option<usize>,
    width: usize,
    bottom: bool,
) -> (Vec<Row>, Vec<usize>, usize, usize) {
    const GAP: usize = 3;
    let n = nodes.len();
    // Each label gets at most an even share of the width, and at least 16.
    let per = (width.saturating_sub(6) / n.max(1))
        .saturating_sub(GAP)
        .max(16);
    let labels: Vec<Vec<String>> = nodes.iter().map(|x| label(x, per)).collect();
    let w = |i: usize| {
        labels[i]
            .iter()
            .map(|l| l.chars().count())
            .max()
            .unwrap_or(0)
    };
    // The widest window around the pick that fits, growing right then left.
    let p = pick.unwrap_or(0).min(n.saturating_sub(1));
    let (mut lo, mut hi) = (p, p + 1);
    let mut used = w(p);
    loop {
        let mut grew = false;
        if hi < n && used + GAP + w(hi) + 4 <= width {
            used += GAP + w(hi);
            hi += 1;
            grew = true;
        }
        if lo > 0 && used + GAP + w(lo - 1) + 4 <= width {
            used += GAP + w(lo - 1);
            lo -= 1;
            grew = true;
        }
        if !grew {
            break;
        }
    }
    let height = (lo..hi).map(|i| labels[i].len()).max().unwrap_or(1);
    let mut rows = vec![blank(width); height];
    // The counts of labels left out, on the row the edges meet.
    let edge_row = if bottom { height - 1 } else { 0 };
    let dim = Style::default().fg(Color::DarkGray);
    if lo > 0 {
        for (k, c) in format!("◂{lo}").chars().enumerate() {
            rows[edge_row][k] = (c, dim);
        }
    }
    let right = n - hi;
    if right > 0 {
        let tag: Vec<char> = format!("{right}▸").chars().collect();
        for (k, c) in tag.iter().enumerate() {
            rows[edge_row][width - tag.len() + k] = (*c, dim);
        }
    }
    let mut x = width.saturating_sub(used) / 2;
    let mut anchors = Vec::new();
    for i in lo..hi {
        let st = style(&nodes[i], pick == Some(i));
        let top = if bottom { height - labels[i].len() } else { 0 };
        for (j, line) in labels[i].iter().enumerate() {
            for (k, c) in line.chars().enumerate() {
                if x + k < width {
                    rows[top + j][x + k] = (c, st);
                }
            }
        }
        anchors.push((x + w(i) / 2).min(width.saturating_sub(1)));
        x += w(i) + GAP;
    }
    (rows, anchors, lo, right)
}

/// The edges between `ups` (columns that come down into the bus) and
/// `downs` (columns that go down out of it), in one row.
fn bus(ups: &[usize], downs: &[usize], width: usize) -> Row {
    let mut row = blank(width);
    let all: Vec<usize> = ups.iter().chain(downs).copied().collect();
    let (Some(&lo), Some(&hi)) = (all.iter().min(), all.iter().max()) else {
        return row;
    };
    let edge = Style::default().fg(Color::Blue);
    for (c, cell) in row.iter_mut().enumerate().take(hi + 1).skip(lo) {
        let (u, d) = (ups.contains(&c), downs.contains(&c));
        let (l, r) = (c > lo, c < hi);
        let ch = match (u, d, l, r) {
            (true, true, true, true) => '┼',
            (true, true, true, false) => '┤',
            (true, true, false, true) => '├',
            (true, true, false, false) => '│',
            (true, false, true, true) => '┴',
            (true, false, true, false) => '┘',
            (true, false, false, true) => '└',
            (true, false, false, false) => '│',
            (false, true, true, true) => '┬',
            (false, true, true, false) => '┐',
            (false, true, false, true) => '┌',
            (false, true, false, false) => '│',
            (false, false, ..) => '─',
        };
        *cell = (ch, edge);
    }
    row
}

fn marks(cols: &[usize], ch: char, width: usize) -> Row {
    let mut row = blank(width);
    for &c in cols {
        if c < width {
            row[c] = (ch, Style::default().fg(Color::Blue));
        }
    }
    row
}

/// The neighbourhood drawn in `width` columns. `pick` indexes the parents
/// then the children. The last lines name the picked variable in full.
pub fn draw(n: &Neighbourhood, pick: Option<usize>, width: usize) -> Vec<Line<'static>> {
    let width = width.max(24);
    let mut rows: Vec<Row> = Vec::new();
    let np = n.parents.len();
    let (centre_rows, centre_anchor, ..) =
        row_of(std::slice::from_ref(&n.centre), None, width, false);
    let cx = centre_anchor[0];
    if n.parents.is_empty() {
        let mut r = blank(width);
        let text = "no causes in the model: its value is given (exogenous)";
        for (k, c) in text.chars().enumerate().take(width) {
            r[k] = (c, Style::default().fg(Color::DarkGray));
        }
        rows.push(r);
    } else {
        let (prows, anchors, ..) = row_of(&n.parents, pick.filter(|&p| p < np), width, true);
        rows.extend(prows);
        rows.push(marks(&anchors, '│', width));
        rows.push(bus(&anchors, &[cx], width));
        rows.push(marks(&[cx], '▼', width));
    }
    rows.extend(centre_rows);
    if n.children.is_empty() {
        let mut r = blank(width);
        let text = "no effects in the model";
        for (k, c) in text.chars().enumerate().take(width) {
            r[k] = (c, Style::default().fg(Color::DarkGray));
        }
        rows.push(r);
    } else {
        let (crows, anchors, ..) = row_of(
            &n.children,
            pick.and_then(|p| p.checked_sub(np)),
            width,
            false,
        );
        rows.push(marks(&[cx], '│', width));
        rows.push(bus(&[cx], &anchors, width));
        rows.push(marks(&anchors, '▼', width));
        rows.extend(crows);
    }
    let mut lines: Vec<Line> = rows.into_iter().map(to_line).collect();
    let picked = pick.and_then(|p| n.parents.iter().chain(&n.children).nth(p));
    let (what, x) = match picked {
        Some(x) => ("picked", x),
        None => ("centre", &n.centre),
    };
    lines.push(Line::from(""));
    // The variable in full, wrapped: a long value is an answer's point.
    for row in textwrap::wrap(&format!("{what}: {} = {}", x.name, x.value), width) {
        lines.push(Line::from(Span::styled(
            row.into_owned(),
            Style::default().add_modifier(Modifier::BOLD),
        )));
    }
    // The hint whole, or a shorter one whole: never cut mid-word.
    let hint = crate::tui::view::first_fitting(
        &[
            "←→ pick a cause or effect · Enter: centre on it · Esc: back to the variable asked about",
            "←→ pick · Enter: centre on it · Esc: back",
            "Esc: back",
        ],
        width,
    );
    lines.push(Line::from(Span::styled(
        hint,
        Style::default().fg(Color::DarkGray),
    )));
    lines
}
