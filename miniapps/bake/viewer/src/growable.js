// Typed arrays that grow by doubling, so streamed parsing never holds JS number arrays.
export class Growable {
  constructor(Type, capacity = 1024) {
    this.Type = Type;
    this.data = new Type(capacity);
    this.length = 0;
  }

  reserve(extra) {
    const need = this.length + extra;
    if (need <= this.data.length) return;
    let cap = this.data.length * 2;
    while (cap < need) cap *= 2;
    const next = new this.Type(cap);
    next.set(this.data.subarray(0, this.length));
    this.data = next;
  }

  push(value) {
    if (this.length === this.data.length) this.reserve(1);
    this.data[this.length++] = value;
  }

  push3(a, b, c) {
    this.reserve(3);
    this.data[this.length] = a;
    this.data[this.length + 1] = b;
    this.data[this.length + 2] = c;
    this.length += 3;
  }

  append(array) {
    this.reserve(array.length);
    this.data.set(array, this.length);
    this.length += array.length;
  }

  // A right-sized copy (transferable to the page).
  take() {
    return this.data.slice(0, this.length);
  }
}
