//! The flash interface's sequences on a model of its registers: sticky error flags, an
//! interface busy for a while after each start, an operation refused (`PGSERR`) when it is
//! started while busy or with the wrong operation selected.

use imu_app::flash::{erase, program, FlashFault, FlashInterface};

const PGSERR: u8 = 1 << 4;
const WRPERR: u8 = 1 << 1;

/// A register-level model of the F411's flash interface.
#[derive(Default)]
struct Model {
    /// Polls of `busy` left before the operation in progress ends.
    busy_for: std::cell::Cell<u32>,
    errors: u8,
    ser: bool,
    pg: bool,
    snb: Option<u8>,
    /// Sectors erased, bytes programmed (address, byte), in order.
    erased: Vec<u8>,
    programmed: Vec<(usize, u8)>,
    /// Sectors that are write protected.
    protected: Vec<u8>,
    /// Register writes made while an operation was running (RM0383: not allowed).
    while_busy: u32,
}

impl Model {
    fn running(&self) -> bool {
        self.busy_for.get() > 0
    }
    fn touch(&mut self) {
        if self.running() {
            self.while_busy += 1;
        }
    }
}

impl FlashInterface for Model {
    fn busy(&self) -> bool {
        let left = self.busy_for.get();
        self.busy_for.set(left.saturating_sub(1));
        left > 0
    }
    fn errors(&self) -> u8 {
        self.errors
    }
    fn clear_errors(&mut self) {
        self.errors = 0;
    }
    fn select_erase(&mut self, snb: u8) {
        self.touch();
        self.ser = true;
        self.pg = false;
        self.snb = Some(snb);
    }
    fn start(&mut self) {
        self.touch();
        match (self.ser, self.pg, self.snb) {
            (true, false, Some(s)) if self.protected.contains(&s) => self.errors |= WRPERR,
            (true, false, Some(s)) => {
                self.erased.push(s);
                self.busy_for.set(5);
            }
            _ => self.errors |= PGSERR,
        }
    }
    fn select_program(&mut self) {
        self.touch();
        self.ser = false;
        self.pg = true;
    }
    fn write(&mut self, addr: usize, byte: u8) {
        self.touch();
        if self.pg && !self.ser {
            self.programmed.push((addr, byte));
            self.busy_for.set(2);
        } else {
            self.errors |= PGSERR;
        }
    }
    fn deselect(&mut self) {
        self.touch();
        self.ser = false;
        self.pg = false;
    }
}

#[test]
fn a_stray_error_does_not_fail_every_later_operation() {
    // An error flag left set by anything before (the HAL never cleared them): the next
    // erase and program clear it first, and succeed.
    let mut m = Model {
        errors: PGSERR,
        ..Model::default()
    };
    assert_eq!(erase(&mut m, 1), Ok(()));
    m.errors = PGSERR;
    assert_eq!(program(&mut m, 0x0800_4000, &[1, 2, 3]), Ok(()));
    assert_eq!(m.erased, [1]);
    assert_eq!(
        m.programmed,
        [(0x0800_4000, 1), (0x0800_4001, 2), (0x0800_4002, 3)]
    );
    assert_eq!(m.errors, 0);
}

#[test]
fn nothing_starts_while_the_interface_is_busy_and_each_operation_ends_deselected() {
    let mut m = Model::default();
    m.busy_for.set(7); // an operation from before still running
    assert_eq!(erase(&mut m, 2), Ok(()));
    assert_eq!(program(&mut m, 0x0800_8000, &[9; 20]), Ok(()));
    assert_eq!(erase(&mut m, 1), Ok(()));
    assert_eq!(m.while_busy, 0, "a register written while busy");
    assert!(!m.ser && !m.pg, "left selected");
    assert!(!m.running(), "returned before the last operation ended");
    assert_eq!(m.erased, [2, 1]);
    assert_eq!(m.programmed.len(), 20);
}

#[test]
fn a_failed_operation_reports_its_flags_and_leaves_none_behind() {
    let mut m = Model {
        protected: vec![2],
        ..Model::default()
    };
    assert_eq!(erase(&mut m, 2), Err(FlashFault { errors: WRPERR }));
    assert_eq!(m.errors, 0, "the flags are cleared after they are reported");
    assert!(!m.ser);
    // The next operation is not blamed for it.
    assert_eq!(erase(&mut m, 1), Ok(()));
    assert_eq!(m.erased, [1]);
}

#[test]
fn programming_stops_at_the_first_byte_that_fails() {
    // Programming selected, then something deselects it (a sequence error): the bytes
    // after the failing one are not written, and the fault names the sequence error.
    struct Dropping(Model, usize, u32);
    impl FlashInterface for Dropping {
        fn busy(&self) -> bool {
            self.0.busy()
        }
        fn errors(&self) -> u8 {
            self.0.errors()
        }
        fn clear_errors(&mut self) {
            self.0.clear_errors();
        }
        fn select_erase(&mut self, snb: u8) {
            self.0.select_erase(snb);
        }
        fn start(&mut self) {
            self.0.start();
        }
        fn select_program(&mut self) {
            self.0.select_program();
        }
        fn write(&mut self, addr: usize, byte: u8) {
            self.2 += 1;
            if self.0.programmed.len() == self.1 {
                self.0.pg = false;
            }
            self.0.write(addr, byte);
        }
        fn deselect(&mut self) {
            self.0.deselect();
        }
    }
    let mut d = Dropping(Model::default(), 3, 0);
    assert_eq!(
        program(&mut d, 0x0800_4000, &[1, 2, 3, 4, 5, 6]),
        Err(FlashFault { errors: PGSERR })
    );
    assert_eq!(d.0.programmed.len(), 3);
    assert_eq!(d.2, 4, "no byte is written after the one that failed");
    assert_eq!(d.0.errors, 0);
}
