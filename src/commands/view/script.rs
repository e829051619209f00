//! `meadow view --script FILE`: timed input, one action per line, so a demo
//! can be recorded and the viewer tested without a person.
//!
//! ```text
//! # seconds after the first frame, then what happens
//! 0.5  key space          # any key the viewer knows: space . [ ] l v p h o b esc
//! 0.6  key up             # wind: up down (inflow speed), left right (heading)
//! 1.0  hold w 0.5         # hold a key (w a s d q e) for 0.5 s
//! 1.5  drag 40 -10        # look: a mouse drag of (40, -10) pixels
//! 2.0  wheel 2            # flying speed up two notches
//! 2.2  click 320 250      # a click at pixel (320, 250): a gust drops there
//! 2.3  key b              # a ball on the ground the window's middle looks at
//! 2.4  roll 400 260       # a right click at pixel (400, 260): the ball rolls there
//! 2.5  resize 640 360     # the window's inner size
//! 3.0  close              # the window's close button
//! ```

use crate::error::{Error, Result};

/// What the viewer does on a key or a scripted line.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Esc: quit.
    Quit,
    /// The window closed.
    Close,
    Pause,
    /// One simulation step (`.`), pausing first.
    Step,
    Slower,
    Faster,
    ToggleLod,
    CycleView,
    Screenshot,
    /// H: the keys, in the overlay and on the terminal.
    Help,
    /// O: the overlay shown or hidden.
    ToggleOverlay,
    /// Up and down arrows: the inflow (or, with none, the sources) this
    /// many steps stronger (negative: weaker).
    WindSpeed(i32),
    /// Left and right arrows: the wind's heading turned this many steps
    /// anticlockwise seen from above (negative: clockwise).
    WindTurn(i32),
    /// A click (press and release without dragging) at this pixel of the
    /// window: a gust drops on the ground under it.
    Click(f32, f32),
    /// B: a ball brought onto the ground where the window's middle looks,
    /// or taken away.
    Ball,
    /// A right click at this pixel: the ball rolls to the ground under it
    /// (brought there first if it is away).
    RollTo(f32, f32),
    /// Hold a flying key for this many seconds.
    Hold(char, f64),
    /// Look around by a mouse drag of (x, y) pixels.
    Drag(f32, f32),
    /// Flying speed up (positive) or down by notches.
    Wheel(f32),
    Resize(u32, u32),
}

/// The keys that move the camera while held: forward, left, back, right,
/// down, up.
pub const FLYING_KEYS: [char; 6] = ['w', 'a', 's', 'd', 'q', 'e'];

impl Action {
    /// The action of a key pressed once, by the character it types (or
    /// `space`, `esc`).
    pub fn of_key(name: &str) -> Option<Self> {
        Some(match name {
            "esc" => Self::Quit,
            "space" | " " => Self::Pause,
            "." => Self::Step,
            "[" => Self::Slower,
            "]" => Self::Faster,
            "l" => Self::ToggleLod,
            "v" => Self::CycleView,
            "p" => Self::Screenshot,
            "h" => Self::Help,
            "o" => Self::ToggleOverlay,
            "b" => Self::Ball,
            "up" => Self::WindSpeed(1),
            "down" => Self::WindSpeed(-1),
            "left" => Self::WindTurn(1),
            "right" => Self::WindTurn(-1),
            _ => return None,
        })
    }
}

/// The keys and what they do, as H shows them (overlay and terminal).
pub const KEYS: [(&str, &str); 16] = [
    ("W A S D", "fly forward, left, back, right"),
    ("Q E", "fly down, up"),
    ("drag", "look around"),
    ("wheel", "flying speed"),
    ("space", "pause"),
    (".", "one step"),
    ("[ ]", "time slower, faster"),
    ("L", "level of detail on/off"),
    ("V", "views: shaded, lod, motion"),
    ("P", "screenshot"),
    ("up down", "wind stronger, weaker"),
    ("left right", "turn the wind's heading"),
    ("click", "a gust on the ground, along the heading"),
    ("B", "a ball: bring it where you look, take it away"),
    ("right click", "roll the ball there"),
    ("O H Esc", "overlay, these keys, quit"),
];

/// `KEYS` as lines of text.
pub fn help() -> String {
    KEYS.iter()
        .map(|(keys, what)| format!("{keys:>10}  {what}"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Timed actions, in time order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Script {
    pub actions: Vec<(f64, Action)>,
    /// The first line whose time comes before an earlier line's, said: the
    /// actions run in time order, not the file's.
    pub reordered: Option<String>,
}

/// The longest a script may run, seconds.
const MAX_TIME: f64 = 24.0 * 3600.0;

/// The action a script line's `words` (after its time) name; `bad`
/// makes the line's error from what is wrong.
fn action_of(words: &[&str], bad: &dyn Fn(&str) -> Error) -> Result<Action> {
    let number = |k: usize| -> Result<f64> {
        words
            .get(k)
            .and_then(|w| w.parse::<f64>().ok())
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad("a number is missing"))
    };
    Ok(match (words.get(1).copied(), words.len()) {
        (Some("key"), 3) => Action::of_key(words[2])
            .ok_or_else(|| bad("no such key (space . [ ] l v p h o b esc up down left right)"))?,
        (Some("hold"), 4) => {
            let key = words[2]
                .chars()
                .next()
                .filter(|c| words[2].len() == 1 && FLYING_KEYS.contains(c))
                .ok_or_else(|| bad("only w a s d q e can be held"))?;
            let seconds = number(3)?;
            if !(0.0..=60.0).contains(&seconds) {
                return Err(bad("hold for 0..=60 seconds"));
            }
            Action::Hold(key, seconds)
        }
        (Some("drag"), 4) => Action::Drag(number(2)? as f32, number(3)? as f32),
        (Some("wheel"), 3) => Action::Wheel(number(2)? as f32),
        (Some(click @ ("click" | "roll")), 4) => {
            let (x, y) = (number(2)?, number(3)?);
            if x < 0.0 || y < 0.0 {
                return Err(bad("a click is at a pixel, x and y >= 0"));
            }
            if click == "click" {
                Action::Click(x as f32, y as f32)
            } else {
                Action::RollTo(x as f32, y as f32)
            }
        }
        (Some("resize"), 4) => {
            let side = |v: f64| (1.0..=16384.0).contains(&v).then_some(v as u32);
            match (side(number(2)?), side(number(3)?)) {
                (Some(w), Some(h)) => Action::Resize(w, h),
                _ => return Err(bad("a size is 1..=16384 pixels a side")),
            }
        }
        (Some("close"), 2) => Action::Close,
        _ => return Err(bad("unknown action or wrong number of words")),
    })
}

impl Script {
    /// Parses a script; an error names the file, the line and what to write.
    pub fn parse(name: &str, text: &str) -> Result<Self> {
        let mut actions = Vec::new();
        let mut reordered = None;
        let mut latest: Option<(usize, f64)> = None;
        for (i, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let bad = |what: &str| {
                Error::InvalidInput(format!(
                    "{name} line {}: {what} in {line:?}; write SECONDS ACTION, e.g. \"1.5 key space\" \
                     (the actions: key, hold, drag, wheel, click, roll, resize, close)",
                    i + 1
                ))
            };
            let words: Vec<&str> = line.split_whitespace().collect();
            let time: f64 = words[0]
                .parse()
                .ok()
                .filter(|t: &f64| (0.0..=MAX_TIME).contains(t))
                .ok_or_else(|| bad("the time is not a number of seconds in 0..=86400"))?;
            let action = action_of(&words, &bad)?;
            actions.push((time, action));
            match latest {
                Some((line, before)) if time < before => {
                    reordered.get_or_insert_with(|| {
                        format!(
                            "{name} line {}: {time} s comes before line {line}'s {before} s; the actions run in time order, not the file's",
                            i + 1
                        )
                    });
                }
                _ => latest = Some((i + 1, time)),
            }
        }
        // Stable: actions at the same time happen in the file's order.
        actions.sort_by(|a, b| a.0.total_cmp(&b.0));
        Ok(Self { actions, reordered })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_action_parses_and_comes_in_time_order() {
        let text = "# a demo\n2 close\n0.5 key space\n1 hold w 0.5  # forward\n\
                    1 drag 40 -10\n1.5 wheel -2\n1.7 resize 640 360\n0.6 key .\n\
                    1.8 key up\n1.8 key right\n1.9 click 10 20.5\n1.9 key o\n\
                    1.95 key b\n1.95 roll 30 40\n";
        let s = Script::parse("demo", text).unwrap();
        assert_eq!(
            s.reordered.as_deref(),
            Some("demo line 3: 0.5 s comes before line 2's 2 s; the actions run in time order, not the file's")
        );
        assert_eq!(
            Script::parse("in order", "0.5 key p\n1 key p\n1 key o\n")
                .unwrap()
                .reordered,
            None
        );
        assert_eq!(
            s.actions,
            vec![
                (0.5, Action::Pause),
                (0.6, Action::Step),
                (1.0, Action::Hold('w', 0.5)),
                (1.0, Action::Drag(40.0, -10.0)),
                (1.5, Action::Wheel(-2.0)),
                (1.7, Action::Resize(640, 360)),
                (1.8, Action::WindSpeed(1)),
                (1.8, Action::WindTurn(-1)),
                (1.9, Action::Click(10.0, 20.5)),
                (1.9, Action::ToggleOverlay),
                (1.95, Action::Ball),
                (1.95, Action::RollTo(30.0, 40.0)),
                (2.0, Action::Close),
            ]
        );
    }

    #[test]
    fn a_bad_line_is_named_with_what_to_write() {
        for (text, says) in [
            ("x key space", "line 1: the time is not a number"),
            ("1 key z", "no such key"),
            ("\n1 hold p 1", "line 2: only w a s d q e can be held"),
            ("1 resize 0 10", "a size is 1..=16384"),
            ("1 jump", "unknown action"),
            ("-1 close", "the time is not"),
            ("1 drag 3", "unknown action or wrong number"),
            ("1 wheel NaN", "a number is missing"),
            ("1 click -3 4", "a click is at a pixel"),
            ("1 roll -3 4", "a click is at a pixel"),
            ("1 click 3", "unknown action or wrong number"),
        ] {
            let e = Script::parse("s.txt", text).unwrap_err().to_string();
            assert!(e.starts_with("s.txt line"), "{text}: {e}");
            assert!(e.contains(says), "{text}: {e}");
            assert!(!e.contains('\n'), "{e}");
        }
    }
}
