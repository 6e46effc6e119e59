//! The SIXpack 2's requests as the simulator reads them, from its own
//! reading of the manual (§6.1.1, §6.2, §7): 9 bytes `ADDR CMD P0..P6`, no
//! checksum, multi-byte fields least significant byte first, signed fields
//! two's complement. (The console's codec in `protocol::sixpack2` reads
//! the same manual on its own: each checks the other.)

/// Bytes in a request (§6.2.2: "All 9 Bytes must be sent").
pub const REQUEST_LEN: usize = 9;

/// One command of the instruction set (§8), as data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CommandInfo {
    pub code: u8,
    /// The §7 heading.
    pub name: &'static str,
    /// It answers (§7: a "response" table).
    pub replies: bool,
}

const fn command(code: u8, name: &'static str, replies: bool) -> CommandInfo {
    CommandInfo {
        code,
        name,
        replies,
    }
}

/// The §8 instruction table. $1A ("SetMargin", §6.5.3 only) has no frame
/// layout and is not here; the service commands $F2..$F7 are listed but
/// not simulated (their magic codes are undocumented, digest D10.3).
pub const COMMANDS: &[CommandInfo] = &[
    command(0x10, "Peak current", false),
    command(0x11, "Current control", false),
    command(0x12, "Velocity setting", false),
    command(0x13, "Starting velocity", false),
    command(0x14, "Velocity, Acceleration", false),
    command(0x15, "Motor Parameters", false),
    command(0x16, "Reference Search Parameters", false),
    command(0x17, "Write motor characteristics Table", false),
    command(0x18, "Null Point-Offset and -Range", false),
    command(0x19, "PI-Parameter", false),
    command(0x20, "Query Position and Activity", true),
    command(0x21, "Query Velocity and Activity", true),
    command(0x22, "Start search of Reference", false),
    command(0x23, "Start trapezoidal Ramp", false),
    command(0x24, "Activate PI-Controller on Target Position", false),
    command(0x25, "Start Rotation / change Rotation Velocity", false),
    command(0x26, "Set Target Position", false),
    command(0x27, "Set actual Position", false),
    command(
        0x28,
        "Query all Motor Activities, Request delayed Response",
        true,
    ),
    command(0x29, "Start trapezoidal Ramp in parallel", false),
    command(0x2A, "Stop Motors selectively or synchronously", false),
    command(0x2B, "Abort reference search", false),
    command(
        0x30,
        "Read Motor Input Channels and additional Inputs",
        true,
    ),
    command(
        0x31,
        "Setting the Limits for the Stop Function left/right",
        false,
    ),
    command(0x32, "Setting of additional Outputs", false),
    command(0x33, "Function of the ready Output", false),
    command(0x40, "Adjust RS 232 / RS 485 Baud rate", false),
    command(0x41, "Setting of Timeout for Abort of Packet", false),
    command(0x42, "Change Address of Unit", false),
    command(0x43, "Read out Information about Unit", true),
    command(0x44, "Configure /query RS 232-operating Mode via CAN", true),
    command(0x50, "Start multi-dimensional linear Interpolation", false),
    command(0xCC, "Complete Hardware Reset", false),
    command(0xF2, "Enable erasing and writing the Flash-Memory", true),
    command(0xF3, "Program Flash Memory", false),
    command(0xF4, "Query flash Memory Check-Sum", true),
    command(0xF5, "Read out Flash-Memory", true),
    command(0xF6, "Write EEPROM", true),
    command(0xF7, "Read EEPROM", true),
];

/// The table row of `code`.
pub fn info(code: u8) -> Option<&'static CommandInfo> {
    COMMANDS.iter().find(|c| c.code == code)
}

/// A request, its fields read and motor numbers checked (0..5). Values are
/// raw: their §7 ranges are checked where they are applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Command {
    PeakCurrent {
        motor: usize,
        value: u8,
    },
    CurrentControl {
        motor: usize,
        index: [u8; 4],
        t0: u16,
    },
    ClockDivider {
        clkdiv: u8,
    },
    VMinVStart {
        motor: usize,
        vmin: u16,
        vstart: u16,
        div: u8,
    },
    AMaxVMax {
        motor: usize,
        amax: u16,
        vmax: u16,
    },
    MotorParameters {
        motor: usize,
        poslimit: u32,
        flags: u16,
    },
    RefSearchParameters {
        motor: usize,
        vrefmax: u16,
        debounce_mask: u16,
        stop_after: bool,
    },
    MotorTable {
        start: u8,
        entries: [u8; 4],
    },
    NullPointOffset {
        motor: usize,
        offset: i32,
        range: u16,
    },
    PiParameters {
        motor: usize,
        propdiv: u8,
        intdiv: u16,
        intclip: u16,
        intinpclip: u8,
    },
    GetPosition {
        motor: usize,
        respond_to: u8,
    },
    GetVelocity {
        motor: usize,
        respond_to: u8,
    },
    StartReferenceSearch {
        motor: usize,
    },
    StartRamp {
        motor: usize,
        target: i32,
    },
    StartPi {
        motor: usize,
        target: i32,
    },
    Rotate {
        motor: usize,
        velocity: i16,
    },
    SetTarget {
        motor: usize,
        target: i32,
    },
    SetPosition {
        motor: usize,
        position: i32,
    },
    GetActivities {
        respond_to: u8,
        wait_mask: u8,
    },
    StartRampParallel {
        mask: u8,
    },
    StopMotors {
        mask: u8,
    },
    AbortReferenceSearch {
        motor: usize,
    },
    GetInputs {
        channel: u8,
        respond_to: u8,
    },
    StopSwitchLimits {
        channel: u8,
        min_left: u16,
        max_right: u16,
    },
    Outputs {
        ttlout1: bool,
        ttlio1_input: bool,
        ttlio1_level: bool,
        ttlout1_ready: bool,
    },
    ReadyMask {
        active: u8,
        search: u8,
    },
    BaudRate {
        divisor: u16,
        switch_over: u16,
    },
    PacketTimeout {
        timeout: u16,
    },
    UnitAddress {
        address: u8,
    },
    GetUnitInformation {
        respond_to: u8,
    },
    Rs232ViaCan {
        respond_to: u8,
        forward_to: u8,
        bytes: u8,
    },
    StartInterpolation {
        mask: u8,
    },
    HardwareReset {
        key: u8,
    },
}

/// Why a frame does nothing (it is dropped without a reply, digest D10.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unread {
    /// Not in the instruction set, or a service command (not simulated).
    UnknownCommand(u8),
    /// A motor number above 5.
    NoSuchMotor(u8),
}

/// Motor masks use bits 0..5 (bit 0 = motor 0, bit 5 = motor 5).
pub const MOTOR_MASK: u8 = 0x3F;

impl Command {
    /// Read the command and parameters of a request (its address byte is
    /// the receiver's business).
    pub fn read(frame: &[u8; REQUEST_LEN]) -> Result<Command, Unread> {
        let [_, code, p @ ..] = *frame;
        let u16_at = |i: usize| u16::from_le_bytes([p[i], p[i + 1]]);
        let i32_at = |i: usize| i32::from_le_bytes([p[i], p[i + 1], p[i + 2], p[i + 3]]);
        let bit = |i: usize| p[i] & 1 != 0;
        let motor = || {
            if usize::from(p[0]) < super::settings::MOTORS {
                Ok(usize::from(p[0]))
            } else {
                Err(Unread::NoSuchMotor(p[0]))
            }
        };
        let command = match code {
            0x10 => Command::PeakCurrent {
                motor: motor()?,
                value: p[1],
            },
            0x11 => Command::CurrentControl {
                motor: motor()?,
                index: [p[1], p[2], p[3], p[4]],
                t0: u16_at(5),
            },
            0x12 => Command::ClockDivider { clkdiv: p[0] },
            0x13 => Command::VMinVStart {
                motor: motor()?,
                vmin: u16_at(1),
                vstart: u16_at(3),
                div: p[5],
            },
            0x14 => Command::AMaxVMax {
                motor: motor()?,
                amax: u16_at(1),
                vmax: u16_at(3),
            },
            0x15 => Command::MotorParameters {
                motor: motor()?,
                poslimit: u32::from_le_bytes([p[1], p[2], p[3], p[4]]),
                flags: u16_at(5),
            },
            0x16 => Command::RefSearchParameters {
                motor: motor()?,
                vrefmax: u16_at(1),
                debounce_mask: u16_at(3),
                stop_after: bit(5),
            },
            0x17 => Command::MotorTable {
                start: p[0],
                entries: [p[1], p[2], p[3], p[4]],
            },
            0x18 => Command::NullPointOffset {
                motor: motor()?,
                offset: i32_at(1),
                range: u16_at(5),
            },
            0x19 => Command::PiParameters {
                motor: motor()?,
                propdiv: p[1],
                intdiv: u16_at(2),
                intclip: u16_at(4),
                intinpclip: p[6],
            },
            0x20 => Command::GetPosition {
                motor: motor()?,
                respond_to: p[1],
            },
            0x21 => Command::GetVelocity {
                motor: motor()?,
                respond_to: p[1],
            },
            0x22 => Command::StartReferenceSearch { motor: motor()? },
            0x23 => Command::StartRamp {
                motor: motor()?,
                target: i32_at(1),
            },
            0x24 => Command::StartPi {
                motor: motor()?,
                target: i32_at(1),
            },
            0x25 => Command::Rotate {
                motor: motor()?,
                velocity: u16_at(1) as i16,
            },
            0x26 => Command::SetTarget {
                motor: motor()?,
                target: i32_at(1),
            },
            0x27 => Command::SetPosition {
                motor: motor()?,
                position: i32_at(1),
            },
            0x28 => Command::GetActivities {
                respond_to: p[0],
                wait_mask: p[1] & MOTOR_MASK,
            },
            0x29 => Command::StartRampParallel {
                mask: p[0] & MOTOR_MASK,
            },
            0x2A => Command::StopMotors {
                mask: p[0] & MOTOR_MASK,
            },
            0x2B => Command::AbortReferenceSearch { motor: motor()? },
            0x30 => Command::GetInputs {
                channel: p[0],
                respond_to: p[1],
            },
            0x31 => Command::StopSwitchLimits {
                channel: p[0],
                min_left: u16_at(1),
                max_right: u16_at(3),
            },
            0x32 => Command::Outputs {
                ttlout1: bit(0),
                ttlio1_input: bit(1),
                ttlio1_level: bit(2),
                ttlout1_ready: bit(3),
            },
            0x33 => Command::ReadyMask {
                active: p[0] & MOTOR_MASK,
                search: p[1] & MOTOR_MASK,
            },
            0x40 => Command::BaudRate {
                divisor: u16_at(0),
                switch_over: u16_at(2),
            },
            0x41 => Command::PacketTimeout { timeout: u16_at(0) },
            0x42 => Command::UnitAddress { address: p[0] },
            0x43 => Command::GetUnitInformation { respond_to: p[0] },
            0x44 => Command::Rs232ViaCan {
                respond_to: p[0],
                forward_to: p[1],
                bytes: p[2],
            },
            0x50 => Command::StartInterpolation {
                mask: p[0] & MOTOR_MASK,
            },
            0xCC => Command::HardwareReset { key: p[0] },
            other => return Err(Unread::UnknownCommand(other)),
        };
        Ok(command)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(hex: &str) -> Result<Command, Unread> {
        let bytes: Vec<u8> = hex
            .split_whitespace()
            .map(|b| u8::from_str_radix(b, 16).expect("hex"))
            .collect();
        Command::read(&bytes.try_into().expect("9 bytes"))
    }

    #[test]
    fn the_manuals_frames_read_as_their_stated_values() {
        // §5.5.3.2: Poslimit 10000, NullLeft + MechRef.
        assert_eq!(
            read("00 15 00 10 27 00 00 10 04"),
            Ok(Command::MotorParameters {
                motor: 0,
                poslimit: 10000,
                flags: 0x0410
            })
        );
        assert_eq!(
            read("00 22 00 00 00 00 00 00 00"),
            Ok(Command::StartReferenceSearch { motor: 0 })
        );
        // §5.5.3.4: Poslimit 500000, NullLeft + StopNull + NullPositive.
        assert_eq!(
            read("00 15 00 20 A1 07 00 50 40"),
            Ok(Command::MotorParameters {
                motor: 0,
                poslimit: 500_000,
                flags: 0x4050
            })
        );
        // §5.6.2.2: AMax 200, VMax 400 for Motor 4.
        assert_eq!(
            read("00 14 03 C8 00 90 01 00 00"),
            Ok(Command::AMaxVMax {
                motor: 3,
                amax: 200,
                vmax: 400
            })
        );
        // §5.6.2.1 as its stated values (the printed bytes are erratum E4).
        assert_eq!(
            read("00 13 02 05 00 64 00 02 00"),
            Ok(Command::VMinVStart {
                motor: 2,
                vmin: 5,
                vstart: 100,
                div: 2
            })
        );
    }

    #[test]
    fn signed_fields_are_twos_complement_least_significant_byte_first() {
        assert_eq!(
            read("00 23 05 F0 D8 FF FF 00 00"),
            Ok(Command::StartRamp {
                motor: 5,
                target: -10000
            })
        );
        assert_eq!(
            read("00 25 01 01 FE 00 00 00 00"),
            Ok(Command::Rotate {
                motor: 1,
                velocity: -511
            })
        );
    }

    #[test]
    fn motor_six_and_unknown_codes_are_not_read() {
        assert_eq!(
            read("00 23 06 00 00 00 00 00 00"),
            Err(Unread::NoSuchMotor(6))
        );
        assert_eq!(
            read("00 1A 00 00 00 00 00 00 00"),
            Err(Unread::UnknownCommand(0x1A))
        );
        assert_eq!(
            read("00 F4 00 00 00 00 00 00 00"),
            Err(Unread::UnknownCommand(0xF4))
        );
        assert_eq!(
            read("00 28 00 FF 00 00 00 00 00"),
            Ok(Command::GetActivities {
                respond_to: 0,
                wait_mask: 0x3F
            })
        );
    }

    #[test]
    fn every_replying_command_of_the_table_is_read_but_the_service_ones() {
        for info in COMMANDS {
            let mut frame = [0u8; REQUEST_LEN];
            frame[1] = info.code;
            let read = Command::read(&frame);
            assert_eq!(
                read.is_err(),
                info.code >= 0xF2,
                "{:02X} {}",
                info.code,
                info.name
            );
        }
    }
}
