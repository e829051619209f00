//! Ownership by structure: `DependsOn<T, K>` holds a value and what it
//! needs alive, and drops the value first, whatever the order of the
//! fields of the struct that holds it. An owner whose parts must die in
//! an order says so by its type, not by a comment about field order.

use std::mem::ManuallyDrop;
use std::ops::{Deref, DerefMut};

/// `value`, which uses `keeper` until it is dropped (an egui renderer and
/// the command pool it uploads with; a simulation and the buffer its grass
/// writes; what draws into a window and the window).
pub struct DependsOn<T, K> {
    // Whatever this order, `Drop` drops `value` first.
    keeper: K,
    value: ManuallyDrop<T>,
}

impl<T, K> DependsOn<T, K> {
    pub fn new(value: T, keeper: K) -> Self {
        Self {
            value: ManuallyDrop::new(value),
            keeper,
        }
    }

    /// What the value needs alive.
    pub fn keeper(&self) -> &K {
        &self.keeper
    }

    /// The value and its keeper, both borrowed mutably at once.
    pub fn parts_mut(&mut self) -> (&mut T, &mut K) {
        (&mut self.value, &mut self.keeper)
    }
}

impl<T, K> Deref for DependsOn<T, K> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.value
    }
}

impl<T, K> DerefMut for DependsOn<T, K> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.value
    }
}

impl<T, K> Drop for DependsOn<T, K> {
    fn drop(&mut self) {
        // SAFETY: `value` is dropped once, here; nothing reads it after,
        // and `keeper` is dropped only after this body returns.
        unsafe { ManuallyDrop::drop(&mut self.value) };
    }
}

#[cfg(test)]
mod tests {
    use std::cell::RefCell;
    use std::rc::Rc;

    use super::DependsOn;

    struct Noted(&'static str, Rc<RefCell<Vec<&'static str>>>);

    impl Drop for Noted {
        fn drop(&mut self) {
            self.1.borrow_mut().push(self.0);
        }
    }

    #[test]
    fn the_value_dies_before_its_keeper_whatever_the_field_order() {
        let order = Rc::new(RefCell::new(Vec::new()));
        // `DependsOn` declares its keeper first: by field order alone the
        // keeper would die first.
        struct Holder {
            _keeper_first: DependsOn<Noted, Noted>,
        }
        let holder = Holder {
            _keeper_first: DependsOn::new(
                Noted("value", order.clone()),
                Noted("keeper", order.clone()),
            ),
        };
        drop(holder);
        assert_eq!(*order.borrow(), ["value", "keeper"]);
    }
}
