# Applied by cmake/EphorLcm.cmake to lcm-gen's C++ headers (LCM 1.3.1). Found
# by the fuzz target arm_command (issue 18): two ways in which one malformed
# message made the generated decode() throw std::length_error out of the
# bus's receive callback, killing the process, instead of returning -1:
#
# 1. A string's length field of 0 or less: the decoder assigned length - 1
#    (as size_t: about 2^64) characters. Every message with a header_t
#    (sender) has one. The length counts the terminating NUL, so it is >= 1.
s/^( *)if\((__[A-Za-z0-9_]+) > maxlen - pos\) return -1;$/\1if(\2 <= 0 || \2 > maxlen - pos) return -1;  \/\/ ephor: cmake\/lcm_bound_counts.sed/
# 2. A variable-length array's count: the decoder resized the array to the
#    count it had just read before checking the buffer held that many
#    elements; a negative count threw and a huge one allocated gigabytes for
#    a message of a hundred bytes. Every element takes at least one byte, so
#    a count beyond the bytes left is refused.
s/^( *)this->([A-Za-z0-9_]+)\.resize\(this->([A-Za-z0-9_]+)\);$/\1if (this->\3 < 0 || this->\3 > maxlen - pos) return -1;  \/\/ ephor: cmake\/lcm_bound_counts.sed\n\1this->\2.resize(this->\3);/
# 3. A string holding a NUL byte before its end (found by deputy_orders): the
#    decoder kept it, but LCM's encoders write a string only up to its first
#    NUL while getEncodedSize() counts all of it, so a process that published
#    such a string again (a deputy's status naming a process, a relayed
#    sender) sent a message every receiver dropped as short. No LCM encoder
#    writes one, so it is refused here, as a malformed message, once for
#    every process.
s/^( *)this->([][A-Za-z0-9_]+)\.assign\(\(\(const char\*\)buf\) \+ offset \+ pos, (__[A-Za-z0-9_]+) - +1\);$/&\n\1if (this->\2.find(char(0)) != std::string::npos) return -1;  \/\/ ephor: cmake\/lcm_bound_counts.sed/
