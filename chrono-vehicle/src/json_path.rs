//! The field path at a position of a JSON text. serde_json reports a typed-parse error by
//! line and column; [`path_at`] turns that position into the path of the value there
//! (`axles[0].suspension.spring`), so the error names the field and not only a line.

/// One open container while scanning.
enum Frame {
    /// An object and the key of the member being read (none before the first key).
    Object(Option<String>),
    /// An array and the index of the element being read.
    Array(usize),
}

/// The path of the innermost value that contains the 1-based position (`line`, `column`)
/// of `text`; at a closing `}` or `]` the path of that object or array itself. Empty
/// for the top level.
pub(crate) fn path_at(text: &str, line: usize, column: usize) -> String {
    let mut stack: Vec<Frame> = Vec::new();
    let (mut l, mut c) = (1usize, 0usize);
    let mut expect_key = false;
    let mut chars = text.chars();
    let mut closing = false;
    while let Some(ch) = chars.next() {
        if ch == '\n' {
            l += 1;
            c = 0;
            continue;
        }
        c += 1;
        let at_target = (l, c) >= (line, column);
        match ch {
            '{' => {
                stack.push(Frame::Object(None));
                expect_key = true;
            }
            '[' => {
                stack.push(Frame::Array(0));
                expect_key = false;
            }
            '}' | ']' => {
                if at_target {
                    closing = true;
                    break;
                }
                stack.pop();
                expect_key = false;
            }
            ',' => match stack.last_mut() {
                Some(Frame::Array(i)) => *i += 1,
                Some(Frame::Object(_)) => expect_key = true,
                None => {}
            },
            ':' => expect_key = false,
            '"' => {
                // Read the string (escapes kept as written: keys are plain names).
                let mut s = String::new();
                let mut escape = false;
                for ch in chars.by_ref() {
                    c += 1;
                    if escape {
                        escape = false;
                        s.push(ch);
                    } else if ch == '\\' {
                        escape = true;
                    } else if ch == '"' {
                        break;
                    } else {
                        s.push(ch);
                    }
                }
                if expect_key && let Some(Frame::Object(key)) = stack.last_mut() {
                    *key = Some(s);
                    expect_key = false;
                    continue;
                }
                if (l, c) >= (line, column) {
                    break;
                }
            }
            _ => {}
        }
        if at_target {
            break;
        }
    }
    let n = stack.len();
    let mut path = String::new();
    for (k, frame) in stack.iter().enumerate() {
        // At a closing bracket: the container itself, not its last member.
        if closing && k + 1 == n {
            break;
        }
        match frame {
            Frame::Object(Some(key)) => {
                if !path.is_empty() {
                    path.push('.');
                }
                path.push_str(key);
            }
            Frame::Object(None) => {}
            Frame::Array(i) => path.push_str(&format!("[{i}]")),
        }
    }
    path
}

/// Parse `text` (JSON read from `path`) into `T`; a parse error names `path`, the field
/// path at the error's position and what serde_json said.
pub(crate) fn parse<T: serde::de::DeserializeOwned>(
    text: &str,
    path: &str,
) -> crate::error::Result<T> {
    serde_json::from_str(text).map_err(|e| {
        let at = if e.line() > 0 {
            path_at(text, e.line(), e.column())
        } else {
            String::new()
        };
        let message = if at.is_empty() {
            e.to_string()
        } else {
            format!("at `{at}`: {e}")
        };
        crate::error::VehicleError::Data {
            path: path.to_string(),
            message,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::path_at;

    #[test]
    fn finds_the_member_and_the_container() {
        let text = "{\n \"a\": {\n  \"b\": [1, 2, \"x\"],\n  \"c\": 3\n }\n}";
        // The "x" of a.b[2]: line 3, closing quote at column 18.
        assert_eq!(path_at(text, 3, 17), "a.b[2]");
        assert_eq!(path_at(text, 4, 8), "a.c");
        // The closing brace of `a`.
        assert_eq!(path_at(text, 5, 2), "a");
        assert_eq!(path_at(text, 6, 1), "");
    }
}
