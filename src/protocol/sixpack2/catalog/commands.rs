//! The §7 command table: every command's request and reply fields in
//! frame order, and the names the manual uses without a layout.

use super::*;

// Reply layouts (§7). The first field of `$20`, `$21` and `$30` echoes
// the request's P0.

const POSITION_REPLY: &[Field] = &[
    MOTNO,
    with_unit(
        field("posact", 1, 4, I32, "actual position (signed long)"),
        "µsteps",
    ),
    field("action", 5, 1, FieldKind::Action, "current action"),
    field(
        "stop",
        6,
        1,
        FieldKind::Bit,
        "stop flag: a stop condition has occurred; cleared by this read",
    ),
];

const VELOCITY_REPLY: &[Field] = &[
    MOTNO,
    with_unit(
        field("vact", 1, 2, signed(-32768, 32767), "actual velocity"),
        VELOCITY_UNIT,
    ),
    field("action", 3, 1, FieldKind::Action, "current action"),
];

const ACTIVITIES_REPLY: &[Field] = &[
    field("m0", 0, 1, FieldKind::Action, "action of motor 0 (Motor 1)"),
    field("m1", 1, 1, FieldKind::Action, "action of motor 1 (Motor 2)"),
    field("m2", 2, 1, FieldKind::Action, "action of motor 2 (Motor 3)"),
    field("m3", 3, 1, FieldKind::Action, "action of motor 3 (Motor 4)"),
    field("m4", 4, 1, FieldKind::Action, "action of motor 4 (Motor 5)"),
    field("m5", 5, 1, FieldKind::Action, "action of motor 5 (Motor 6)"),
];

const INPUTS_REPLY: &[Field] = &[
    field("channel", 0, 1, FieldKind::Channel, "channel read"),
    field(
        "analog",
        1,
        2,
        unsigned(0, 65535),
        "analog value 0..1023 (channel 7: 22 counts per volt)",
    ),
    field(
        "ref",
        3,
        1,
        FieldKind::Bit,
        "the channel's reference input (inverted, §7.3)",
    ),
    field(
        "inputs",
        4,
        1,
        FieldKind::InputsAndJumpers,
        "all reference inputs (bit n = motor n) and jumpers JP1 (bit 6), JP2 (bit 7)",
    ),
    field("ttlio1", 5, 1, FieldKind::Bit, "logic state of TTLIO1"),
];

const UNIT_REPLY: &[Field] = &[
    field(
        "firmware",
        0,
        1,
        unsigned(0, 255),
        "firmware revision (148 = V1.4.8)",
    ),
    field(
        "reset",
        1,
        1,
        FieldKind::Bit,
        "reset flag: 1 on the first read after a reset, 0 afterwards",
    ),
    with_unit(
        field(
            "temperature",
            2,
            1,
            signed(-128, 127),
            "temperature of the unit (keep below 85 °C, §3.1)",
        ),
        "°C",
    ),
    field("serial", 3, 2, unsigned(0, 65535), "serial number"),
];

const CAN_RS232_REPLY: &[Field] = &[
    field(
        "txbuffer",
        0,
        1,
        unsigned(0, 255),
        "bytes in the RS-232 send buffer (0 = empty)",
    ),
    field(
        "cts",
        1,
        1,
        FieldKind::Bit,
        "state of the CTS line (inverted)",
    ),
];

const ERASE_REPLY: &[Field] = &[field("erased", 0, 1, unsigned(0, 255), "1 = erase OK")];

const CHECKSUM_REPLY: &[Field] = &[hex(field(
    "checksum",
    0,
    2,
    unsigned(0, 65535),
    "flash checksum (depends on the firmware version)",
))];

const FLASH_DATA_REPLY: &[Field] = &[
    hex(field("d0", 0, 1, unsigned(0, 255), "data byte 0")),
    hex(field("d1", 1, 1, unsigned(0, 255), "data byte 1")),
    hex(field("d2", 2, 1, unsigned(0, 255), "data byte 2")),
    hex(field("d3", 3, 1, unsigned(0, 255), "data byte 3")),
    hex(field("d4", 4, 1, unsigned(0, 255), "data byte 4")),
    hex(field("d5", 5, 1, unsigned(0, 255), "data byte 5")),
    hex(field("d6", 6, 1, unsigned(0, 255), "data byte 6")),
];

const WRITTEN_REPLY: &[Field] = &[field(
    "written",
    0,
    1,
    unsigned(0, 255),
    "1 = writing successful",
)];

/// `$F7`: §7.6 copies the `$F6` table ("1=writing successful"); where the
/// value read goes is unknown (digest E22), so every byte is shown.
const EEPROM_READ_REPLY: &[Field] = &[
    hex(field(
        "p0",
        0,
        1,
        unsigned(0, 255),
        "P0 (\"1=writing successful\", sic)",
    )),
    hex(field("p1", 1, 1, unsigned(0, 255), "P1 (layout unknown)")),
    hex(field("p2", 2, 1, unsigned(0, 255), "P2 (layout unknown)")),
    hex(field("p3", 3, 1, unsigned(0, 255), "P3 (layout unknown)")),
    hex(field("p4", 4, 1, unsigned(0, 255), "P4 (layout unknown)")),
    hex(field("p5", 5, 1, unsigned(0, 255), "P5 (layout unknown)")),
    hex(field("p6", 6, 1, unsigned(0, 255), "P6 (layout unknown)")),
];

const SERVICE: Confirm = Confirm::Always(
    "a service function, not intended for the user: used improperly it can damage the unit \
     permanently (§7.6)",
);

const TARGET: Field = with_unit(
    field("target", 1, 4, I32, "target position (signed long)"),
    "µsteps",
);

const EEPROM_FIELDS: &[Field] = &[
    RESPONSE_REQUIRED,
    hex(field(
        "magic",
        1,
        2,
        unsigned(0, 65535),
        "magic code 2 (not documented)",
    )),
    hex(field("address", 3, 2, unsigned(0, 65535), "EEPROM address")),
    hex(field("value", 5, 2, unsigned(0, 65535), "value")),
];

/// Every command of §7 in the order of §8.
pub const COMMANDS: &[CommandSpec] = &[
    CommandSpec {
        code: 0x10,
        mnemonic: "SetPeakCurrent",
        aliases: &["PeakCurrent", "SetMaxCurrent"],
        heading: "Peak current",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            with_unit(
                field(
                    "peak",
                    1,
                    1,
                    unsigned(0, 255),
                    "peak current = DIP-switch current · peak/256 (§7.1 \"value\")",
                ),
                "/256",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "set for motor pairs 0+1, 2+3, 4+5: only motno 0, 2 and 4 take effect (§7.1); \
               default 128",
    },
    CommandSpec {
        code: 0x11,
        mnemonic: "SetCurrentControl",
        aliases: &[],
        heading: "Current control",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            field(
                "I0",
                1,
                1,
                FieldKind::CurrentIndex,
                "power-down current, after T0 at standstill",
            ),
            field(
                "I1",
                2,
                1,
                FieldKind::CurrentIndex,
                "current when the motor stands at its target",
            ),
            field(
                "I2",
                3,
                1,
                FieldKind::CurrentIndex,
                "current at constant velocity",
            ),
            field(
                "I3",
                4,
                1,
                FieldKind::CurrentIndex,
                "current while accelerating",
            ),
            with_unit(
                field(
                    "T0",
                    5,
                    2,
                    unsigned(1, 65535),
                    "power-down delay (also the DelayTestNull settle time, §6.4.6); firmware \
                     before v1.40 needs even values",
                ),
                "2 ms",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "currents as index 0..8 or as percentages (100% 75% 50% 38% 25% 19% 13% 9% 0%); \
               defaults I0 0%, I1 50%, I2 75%, I3 100%, T0 500",
    },
    CommandSpec {
        code: 0x12,
        mnemonic: "SetClockDivider",
        aliases: &["ClockDivider"],
        heading: "Velocity setting",
        section: "7.1",
        class: Class::Setting,
        fields: &[field(
            "clkdiv",
            0,
            1,
            unsigned(0, 31),
            "clock divider of all motors: f_µstep = 20 MHz/(clkdiv+1)·v/2^(14+div)",
        )],
        reply: None,
        confirm: Confirm::Never,
        note: "global to all motors; change it only with all motors stopped; default 5",
    },
    CommandSpec {
        code: 0x13,
        mnemonic: "SetVMinVStart",
        aliases: &["StartVelocity"],
        heading: "Starting velocity",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            with_unit(
                field(
                    "vmin",
                    1,
                    2,
                    unsigned(0, 511),
                    "slow velocity for locating the switch, always at div 3 (0 = fastest allowed)",
                ),
                VELOCITY_UNIT,
            ),
            with_unit(
                field(
                    "vstart",
                    3,
                    2,
                    unsigned(1, 511),
                    "start and end velocity of every ramp",
                ),
                VELOCITY_UNIT,
            ),
            field(
                "div",
                5,
                1,
                unsigned(0, 3),
                "velocity predivider of this motor",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "change it only with the motor stopped; vmin <= vstart, vstart < (512 >> \
               (3-div)) - 1; defaults vmin 4, vstart 5, div 2",
    },
    CommandSpec {
        code: 0x14,
        mnemonic: "SetAMaxVMax",
        aliases: &[],
        heading: "Velocity, Acceleration",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            field(
                "amax",
                1,
                2,
                unsigned(1, 32767),
                "acceleration: amax/64 is added to the velocity every 2 ms",
            ),
            with_unit(
                field("vmax", 3, 2, unsigned(1, 511), "maximum velocity"),
                VELOCITY_UNIT,
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "takes effect at once, even while moving; 0 < amax <= 64·vstart; defaults \
               amax 128, vmax 511",
    },
    CommandSpec {
        code: 0x15,
        mnemonic: "SetMotorParameters",
        aliases: &[],
        heading: "Motor Parameters",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            with_unit(
                field(
                    "poslimit",
                    1,
                    4,
                    unsigned(0, 0x7FFF_FFFF),
                    "µsteps per revolution (rotary) or total travel (linear): the reference \
                     search drives up to 5/4 of it",
                ),
                "µsteps",
            ),
            hex(field(
                "flags",
                5,
                2,
                FieldKind::Flags(MOTOR_FLAGS),
                "motor type flags by name (NullLeft,MechRef), none, or a number",
            )),
        ],
        reply: None,
        confirm: Confirm::WhenFlag {
            flag: "AutonullCmd",
            why: "AutonullCmd starts a reference search at once (§7.1, the same action as $22)",
        },
        note: "writes the whole flag word: flags not named are cleared (factory word $0AA0 = \
               FilterSwitch,NullCenter,FastRef,DelayTestNull)",
    },
    CommandSpec {
        code: 0x16,
        mnemonic: "SetRefSearchParameters",
        aliases: &[],
        heading: "Reference Search Parameters",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            with_unit(
                field(
                    "vrefmax",
                    1,
                    2,
                    unsigned(1, 511),
                    "fast reference search velocity: vstart <= vrefmax <= vmax",
                ),
                VELOCITY_UNIT,
            ),
            hex(field(
                "debounce",
                3,
                2,
                unsigned(0, 65535),
                "debounce mask of the reference input: $0001 = 0 ms, $0003 = 2 ms … $FFFF = 30 ms",
            )),
            field(
                "stopafter",
                5,
                1,
                FieldKind::Bit,
                "1 = stop after the search, 0 = resume the previous action",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "change it only with the motor stopped; defaults vrefmax 100, debounce $0FFF \
               (22 ms), stopafter 0",
    },
    CommandSpec {
        code: 0x17,
        mnemonic: "WriteMotorTable",
        aliases: &[],
        heading: "Write motor characteristics Table",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            field(
                "index",
                0,
                1,
                FieldKind::OneOf(&[0, 4, 8, 12]),
                "first of the four entries written: 0, 4, 8 or 12",
            ),
            field("e0", 1, 1, unsigned(0, 255), "table entry index+0"),
            field("e1", 2, 1, unsigned(0, 255), "table entry index+1"),
            field("e2", 3, 1, unsigned(0, 255), "table entry index+2"),
            field("e3", 4, 1, unsigned(0, 255), "table entry index+3"),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "16 entries, a quarter sine period, common to all motors; default \
               255·sin((i+0.5)·π/32); all 255 gives full steps (§6.3.2)",
    },
    CommandSpec {
        code: 0x18,
        mnemonic: "SetNullPointOffset",
        aliases: &[],
        heading: "Null Point-Offset and -Range",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            with_unit(
                field(
                    "nulloffset",
                    1,
                    4,
                    I32,
                    "distance between zero point and reference switch (signed long)",
                ),
                "µsteps",
            ),
            with_unit(
                field(
                    "testnullrange",
                    5,
                    2,
                    unsigned(0, 65535),
                    "± range around zero where the switch may be active",
                ),
                "µsteps",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "defaults nulloffset 0, testnullrange 240 (§6.8)",
    },
    CommandSpec {
        code: 0x19,
        mnemonic: "SetPIParameters",
        aliases: &[],
        heading: "PI-Parameter",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            field(
                "propdiv",
                1,
                1,
                unsigned(1, 255),
                "P term = 64·position difference/propdiv",
            ),
            field(
                "intdiv",
                2,
                2,
                unsigned(1, 32767),
                "divisor of the integral part",
            ),
            field(
                "intclip",
                4,
                2,
                unsigned(1, 32767),
                "clip of the position-difference integral",
            ),
            field(
                "intinpclip",
                6,
                1,
                unsigned(0, 255),
                "clip of the position difference integrated each 2 ms (§7.1 labels it \
                 intclip again, digest E14)",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "the controller runs at 500 Hz; defaults 8, 129, 129, 1",
    },
    CommandSpec {
        code: 0x20,
        mnemonic: "GetPositionAndActivity",
        aliases: &[],
        heading: "Query Position and Activity",
        section: "7.2",
        class: Class::Query,
        fields: &[MOTNO, response_at(1)],
        reply: Some(POSITION_REPLY),
        confirm: Confirm::Never,
        note: "answers posact, the action and the stop flag; reading clears the stop flag",
    },
    CommandSpec {
        code: 0x21,
        mnemonic: "GetVelocityAndActivity",
        aliases: &[],
        heading: "Query Velocity and Activity",
        section: "7.2",
        class: Class::Query,
        fields: &[MOTNO, response_at(1)],
        reply: Some(VELOCITY_REPLY),
        confirm: Confirm::Never,
        note: "answers vact (sign = direction) and the action",
    },
    CommandSpec {
        code: 0x22,
        mnemonic: "StartReferenceSearch",
        aliases: &[],
        heading: "Start search of Reference",
        section: "7.2",
        class: Class::Motion,
        fields: &[MOTNO],
        reply: None,
        confirm: Confirm::Always(
            "it stops the motor and drives it to its reference switch or mechanical stop \
             (§7.2)",
        ),
        note: "retries until found or aborted ($2B); then the position is nulloffset and the \
               previous action resumes unless $16 stopafter is 1",
    },
    CommandSpec {
        code: 0x23,
        mnemonic: "StartRamp",
        aliases: &["Ramp"],
        heading: "Start trapezoidal Ramp",
        section: "7.2",
        class: Class::Motion,
        fields: &[MOTNO, TARGET],
        reply: None,
        confirm: Confirm::Never,
        note: "does nothing while the motor is active (a rotation is only stopped); to retarget \
               a ramp send SetTargetPosition then StartRamp with the same target",
    },
    CommandSpec {
        code: 0x24,
        mnemonic: "StartPIControl",
        aliases: &[],
        heading: "Activate PI-Controller on Target Position",
        section: "7.2",
        class: Class::Motion,
        fields: &[MOTNO, TARGET],
        reply: None,
        confirm: Confirm::Always(
            "it switches the motor to PI control and drives it to the target at once, even \
             from standstill (§7.2)",
        ),
        note: "§6.6 calls it SetTargetPosition by mistake: to set a target for $29/$50 use \
               SetTargetPosition ($26)",
    },
    CommandSpec {
        code: 0x25,
        mnemonic: "ConstantRotation",
        aliases: &[],
        heading: "Start Rotation / change Rotation Velocity",
        section: "7.2",
        class: Class::Motion,
        fields: &[
            MOTNO,
            with_unit(
                field(
                    "velocity",
                    1,
                    2,
                    signed(-511, 511),
                    "rotation velocity (0 = decelerate and stop)",
                ),
                VELOCITY_UNIT,
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "takes effect at once, even while the motor is active; changes obey amax",
    },
    CommandSpec {
        code: 0x26,
        mnemonic: "SetTargetPosition",
        aliases: &[],
        heading: "Set Target Position",
        section: "7.2",
        class: Class::Motion,
        fields: &[MOTNO, TARGET],
        reply: None,
        confirm: Confirm::Never,
        note: "changes the target without changing the mode (a running ramp may overshoot and \
               come back); the target for StartRampParallel and StartInterpolation",
    },
    CommandSpec {
        code: 0x27,
        mnemonic: "SetActualPosition",
        aliases: &[],
        heading: "Set actual Position",
        section: "7.2",
        class: Class::Motion,
        fields: &[
            MOTNO,
            with_unit(
                field("position", 1, 4, I32, "new actual position (signed long)"),
                "µsteps",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "can start unintended reference searches when TestNull or StopNull are set",
    },
    CommandSpec {
        code: 0x28,
        mnemonic: "GetAllActivities",
        aliases: &[],
        heading: "Query all Motor Activities, Request delayed Response",
        section: "7.2",
        class: Class::Query,
        fields: &[
            response_at(0),
            optional(
                field(
                    "wait",
                    1,
                    1,
                    FieldKind::MotorMask,
                    "answer only once these motors are inactive (none = at once)",
                ),
                0,
            ),
        ],
        reply: Some(ACTIVITIES_REPLY),
        confirm: Confirm::Never,
        note: "answers the action of all six motors; with a wait mask the answer may come much \
               later (RS-485 with several units: keep the bus idle until it does)",
    },
    CommandSpec {
        code: 0x29,
        mnemonic: "StartRampParallel",
        aliases: &[],
        heading: "Start trapezoidal Ramp in parallel",
        section: "7.2",
        class: Class::Motion,
        fields: &[field(
            "motors",
            0,
            1,
            FieldKind::MotorMask,
            "motors to start towards their SetTargetPosition targets",
        )],
        reply: None,
        confirm: Confirm::Never,
        note: "each motor uses its own vstart/vmax/amax; meant for inactive motors",
    },
    CommandSpec {
        code: 0x2A,
        mnemonic: "StopMotors",
        aliases: &[],
        heading: "Stop Motors selectively or synchronously",
        section: "7.2",
        class: Class::Motion,
        fields: &[field(
            "motors",
            0,
            1,
            FieldKind::MotorMask,
            "motors whose target becomes their actual position",
        )],
        reply: None,
        confirm: Confirm::Never,
        note: "motors faster than vstart overshoot and ramp back to where they were: not an \
               emergency stop",
    },
    CommandSpec {
        code: 0x2B,
        mnemonic: "AbortReferenceSearch",
        aliases: &[],
        heading: "Abort reference search",
        section: "7.2",
        class: Class::Motion,
        fields: &[MOTNO],
        reply: None,
        confirm: Confirm::Never,
        note: "what the motor does afterwards is not stated",
    },
    CommandSpec {
        code: 0x30,
        mnemonic: "GetInputValues",
        aliases: &[],
        heading: "Read Motor Input Channels and additional Inputs",
        section: "7.3",
        class: Class::Query,
        fields: &[
            field(
                "channel",
                0,
                1,
                FieldKind::Channel,
                "0..5 A_In of a motor, 6 external input, 7 supply voltage",
            ),
            response_at(1),
        ],
        reply: Some(INPUTS_REPLY),
        confirm: Confirm::Never,
        note: "answers the analog value, the channel's reference input, all reference inputs \
               with the jumpers, and TTLIO1",
    },
    CommandSpec {
        code: 0x31,
        mnemonic: "SetStopSwitchLimits",
        aliases: &[],
        heading: "Setting the Limits for the Stop Function left/right",
        section: "7.3",
        class: Class::Setting,
        fields: &[
            field(
                "channel",
                0,
                1,
                FieldKind::Channel,
                "A_In channel (0..5 = motor)",
            ),
            field(
                "minleft",
                1,
                2,
                unsigned(0, 65535),
                "stop when moving left below this value (0 = off)",
            ),
            field(
                "maxright",
                3,
                2,
                unsigned(0, 65535),
                "stop when moving right above this value (>= 1023 = off)",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "§6.5.1 calls it CMD $30 by mistake; the voltage should rise to the right",
    },
    CommandSpec {
        code: 0x32,
        mnemonic: "SetOutputs",
        aliases: &[],
        heading: "Setting of additional Outputs",
        section: "7.3",
        class: Class::Setting,
        fields: &[
            field(
                "ttlout1",
                0,
                1,
                FieldKind::Bit,
                "level of TTLOUT1 (1 = READY, 0 = active)",
            ),
            field(
                "ttlio1input",
                1,
                1,
                FieldKind::Bit,
                "TTLIO1 direction (1 = input, 0 = output)",
            ),
            field(
                "ttlio1",
                2,
                1,
                FieldKind::Bit,
                "level of TTLIO1 as an output",
            ),
            field(
                "ready",
                3,
                1,
                FieldKind::Bit,
                "1 = TTLOUT1 works as the ready output",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "TTLOUT1 is high after a reset: programming it low lets the host see a power loss \
               (§3.1)",
    },
    CommandSpec {
        code: 0x33,
        mnemonic: "SetReadyMask",
        aliases: &[],
        heading: "Function of the ready Output",
        section: "7.3",
        class: Class::Setting,
        fields: &[
            field(
                "active",
                0,
                1,
                FieldKind::MotorMask,
                "ready output active while any of these motors moves",
            ),
            field(
                "searching",
                1,
                1,
                FieldKind::MotorMask,
                "ready output active while any of these motors searches its reference",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "defaults all, all",
    },
    CommandSpec {
        code: 0x40,
        mnemonic: "SetBaudRate",
        aliases: &[],
        heading: "Adjust RS 232 / RS 485 Baud rate",
        section: "7.4",
        class: Class::Unit,
        fields: &[
            field(
                "divisor",
                0,
                2,
                unsigned(1, 65535),
                "20 MHz/(16·baud): 130 = 9600, 65 = 19200, 33 = 38400, 22 = 57600",
            ),
            with_unit(
                field(
                    "delay",
                    2,
                    2,
                    unsigned(1, 1000),
                    "transmitter switch-over delay (default 3 = 6 ms)",
                ),
                "2 ms",
            ),
        ],
        reply: None,
        confirm: Confirm::Always(
            "the unit changes its baud rate and the console does not follow: reconnect at the \
             new rate (§7.4; not stored, a reset restores the jumpers' rate)",
        ),
        note: "not stored permanently; to change only the delay resend the current divisor",
    },
    CommandSpec {
        code: 0x41,
        mnemonic: "SetPacketTimeout",
        aliases: &[],
        heading: "Setting of Timeout for Abort of Packet",
        section: "7.4",
        class: Class::Unit,
        fields: &[with_unit(
            field(
                "timeout",
                0,
                2,
                unsigned(2, 65535),
                "a frame not complete within this time is dropped",
            ),
            "2 ms",
        )],
        reply: None,
        confirm: Confirm::Never,
        note: "the factory value is not given",
    },
    CommandSpec {
        code: 0x42,
        mnemonic: "SetUnitAddress",
        aliases: &[],
        heading: "Change Address of Unit",
        section: "7.4",
        class: Class::Unit,
        fields: &[field(
            "address",
            0,
            1,
            unsigned(0, 255),
            "new RS-232/RS-485 address",
        )],
        reply: None,
        confirm: Confirm::Always(
            "the unit answers only at the new address from then on and the console does not \
             follow: change :address (the rotary switches set it again at a reset)",
        ),
        note: "whether the change survives a reset is not stated",
    },
    CommandSpec {
        code: 0x43,
        mnemonic: "GetUnitInformation",
        aliases: &[],
        heading: "Read out Information about Unit",
        section: "7.4",
        class: Class::Query,
        fields: &[response_at(0)],
        reply: Some(UNIT_REPLY),
        confirm: Confirm::Never,
        note: "answers firmware revision, reset flag (cleared by this read), temperature and \
               serial number",
    },
    CommandSpec {
        code: 0x44,
        mnemonic: "ConfigRS232ViaCAN",
        aliases: &[],
        heading: "Configure /query RS 232-operating Mode via CAN",
        section: "7.4",
        class: Class::Query,
        fields: &[
            response_at(0),
            optional(
                field(
                    "forward",
                    1,
                    1,
                    unsigned(0, 255),
                    "CAN response address for bytes received on RS-232 (upper 8 ID bits)",
                ),
                0,
            ),
            optional(
                field(
                    "bytes",
                    2,
                    1,
                    unsigned(0, 8),
                    "bytes per forwarded packet, 1..8 (0 = off)",
                ),
                0,
            ),
        ],
        reply: Some(CAN_RS232_REPLY),
        confirm: Confirm::Never,
        note: "CAN mode only (§6.1.5)",
    },
    CommandSpec {
        code: 0x50,
        mnemonic: "StartInterpolation",
        aliases: &[],
        heading: "Start multi-dimensional linear Interpolation",
        section: "7.5",
        class: Class::Motion,
        fields: &[field(
            "motors",
            0,
            1,
            FieldKind::MotorMask,
            "motors moved together to their SetTargetPosition targets",
        )],
        reply: None,
        confirm: Confirm::Never,
        note: "the motors must stand; all arrive together; query every one before the next \
               command",
    },
    CommandSpec {
        code: 0xCC,
        mnemonic: "HardwareReset",
        aliases: &[],
        heading: "Complete Hardware Reset",
        section: "7.4",
        class: Class::Unit,
        fields: &[optional(
            hex(field(
                "p0",
                0,
                1,
                unsigned(0, 255),
                "\"HW-Reset\": the manual does not give the value (the console sends $00)",
            )),
            0,
        )],
        reply: None,
        confirm: Confirm::Always(
            "every setting is replaced by the factory defaults; the unit takes about 1 s and \
             usually sends one $00 byte (§7.4)",
        ),
        note: "afterwards the $43 reset flag is 1",
    },
    CommandSpec {
        code: 0xF2,
        mnemonic: "FlashEnableErase",
        aliases: &[],
        heading: "Enable erasing and writing the Flash-Memory",
        section: "7.6",
        class: Class::Service,
        fields: &[
            RESPONSE_REQUIRED,
            hex(field(
                "magic",
                1,
                4,
                unsigned(0, 0xFFFF_FFFF),
                "magic code (not documented)",
            )),
        ],
        reply: Some(ERASE_REPLY),
        confirm: SERVICE,
        note: "service function",
    },
    CommandSpec {
        code: 0xF3,
        mnemonic: "FlashProgram",
        aliases: &[],
        heading: "Program Flash Memory",
        section: "7.6",
        class: Class::Service,
        fields: &[
            hex(field("d0", 0, 1, unsigned(0, 255), "data byte 0")),
            hex(field("d1", 1, 1, unsigned(0, 255), "data byte 1")),
            hex(field("d2", 2, 1, unsigned(0, 255), "data byte 2")),
            hex(field("d3", 3, 1, unsigned(0, 255), "data byte 3")),
            hex(field("d4", 4, 1, unsigned(0, 255), "data byte 4")),
            hex(field("d5", 5, 1, unsigned(0, 255), "data byte 5")),
            hex(field("d6", 6, 1, unsigned(0, 255), "data byte 6")),
        ],
        reply: None,
        confirm: SERVICE,
        note: "service function: only after erasing, not to be interrupted",
    },
    CommandSpec {
        code: 0xF4,
        mnemonic: "FlashChecksum",
        aliases: &[],
        heading: "Query flash Memory Check-Sum and abort Programming if necessary",
        section: "7.6",
        class: Class::Service,
        fields: &[response_at(0)],
        reply: Some(CHECKSUM_REPLY),
        confirm: SERVICE,
        note: "service function: also aborts programming and resets the FlashRead pointer",
    },
    CommandSpec {
        code: 0xF5,
        mnemonic: "FlashRead",
        aliases: &[],
        heading: "Read out Flash-Memory",
        section: "7.6",
        class: Class::Service,
        fields: &[response_at(0)],
        reply: Some(FLASH_DATA_REPLY),
        confirm: SERVICE,
        note: "service function: seven bytes at an auto-incrementing pointer",
    },
    CommandSpec {
        code: 0xF6,
        mnemonic: "EepromWrite",
        aliases: &[],
        heading: "Write EEPROM",
        section: "7.6",
        class: Class::Service,
        fields: EEPROM_FIELDS,
        reply: Some(WRITTEN_REPLY),
        confirm: SERVICE,
        note: "service function",
    },
    CommandSpec {
        code: 0xF7,
        mnemonic: "EepromRead",
        aliases: &[],
        heading: "Read EEPROM",
        section: "7.6",
        class: Class::Service,
        fields: EEPROM_FIELDS,
        reply: Some(EEPROM_READ_REPLY),
        confirm: SERVICE,
        note: "service function; §7.6 documents it exactly as EepromWrite (sic), so its layout \
               is a guess",
    },
];

/// A name the manual uses for a command it gives no frame layout for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Undocumented {
    pub name: &'static str,
    pub code: u8,
    pub why: &'static str,
}

/// Commands named outside §7 whose frame is unknown: the console sends them
/// only as raw frames.
pub const UNDOCUMENTED: &[Undocumented] = &[Undocumented {
    name: "SetMargin",
    code: 0x1A,
    why: "§6.5.3 names SetMargin (CMD $1A) but §7 and §8 give no layout (digest E19)",
}];
