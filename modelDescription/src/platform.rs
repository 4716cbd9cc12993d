//! Where a binary goes inside an FMU (FMI 2.0 section 2.4: `binaries/<platform>/<modelIdentifier>.<ext>`).

/// The FMI 2.0 platform directory (`linux64`, `win64`, `darwin64`, ...) for a
/// target OS as `std::env::consts::OS` spells it and a pointer width in bits.
pub fn platform_dir(os: &str, pointer_width: u32) -> Result<String, String> {
    let name = match os {
        "linux" => "linux",
        "windows" => "win",
        "macos" => "darwin",
        other => {
            return Err(format!(
                "FMI 2.0 defines no binary directory for the OS \"{other}\""
            ))
        }
    };
    match pointer_width {
        32 | 64 => Ok(format!("{name}{pointer_width}")),
        w => Err(format!(
            "FMI 2.0 defines no binary directory for {w}-bit targets"
        )),
    }
}

/// The shared-library file extension FMI 2.0 expects on `os` (without the dot).
pub fn library_extension(os: &str) -> Result<&'static str, String> {
    match os {
        "linux" => Ok("so"),
        "windows" => Ok("dll"),
        "macos" => Ok("dylib"),
        other => Err(format!(
            "FMI 2.0 defines no library extension for the OS \"{other}\""
        )),
    }
}

/// The path of the binary in the FMU archive, e.g. `binaries/linux64/BeltDrive.so`.
pub fn binary_path(model_identifier: &str, os: &str, pointer_width: u32) -> Result<String, String> {
    Ok(format!(
        "binaries/{}/{model_identifier}.{}",
        platform_dir(os, pointer_width)?,
        library_extension(os)?
    ))
}

/// [`binary_path`] for the platform this code was compiled for.
pub fn host_binary_path(model_identifier: &str) -> Result<String, String> {
    binary_path(model_identifier, std::env::consts::OS, usize::BITS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths() {
        assert_eq!(
            binary_path("M", "linux", 64).unwrap(),
            "binaries/linux64/M.so"
        );
        assert_eq!(
            binary_path("M", "windows", 32).unwrap(),
            "binaries/win32/M.dll"
        );
        assert_eq!(
            binary_path("M", "macos", 64).unwrap(),
            "binaries/darwin64/M.dylib"
        );
        assert!(binary_path("M", "haiku", 64).unwrap_err().contains("haiku"));
        assert!(platform_dir("linux", 16).is_err());
    }
}
