// EphorSpyProbe: runs lcm-spy (lcm.spy.Spy, in this JVM, with the class path
// tools/ephor spy builds) and checks that it decodes our types: it waits until
// each expected channel has messages that lcm-spy decoded into one of our
// classes (ephor.*), with no undecodable ones, opens lcm-spy's own viewer of
// the first channel, then writes what lcm-spy shows:
//   OUT/channels.txt   lcm-spy's channel table (channel, type, count, ...)
//   OUT/<CHANNEL>.txt  the last message lcm-spy decoded, field by field
//   OUT/spy.png, OUT/viewer.png  the windows, painted into images
// Exits 0 when all expected channels were decoded before the timeout, 1 if
// not (naming them), 2 on bad arguments. Needs a display (Xvfb in tests).
//
//   java -cp <spy class path>:ephor_spy_probe.jar lcm.spy.EphorSpyProbe \
//       --lcm-url=URL --out DIR --timeout-s S CHANNEL...
//
// It lives in package lcm.spy to read lcm-spy's channel table (package-private
// in LCM 1.3.1); nothing of lcm-spy is changed.
package lcm.spy;

import java.awt.Component;
import java.awt.Window;
import java.awt.image.BufferedImage;
import java.io.File;
import java.io.PrintWriter;
import java.lang.reflect.Field;
import java.lang.reflect.Modifier;
import java.util.ArrayList;
import java.util.List;
import javax.imageio.ImageIO;
import javax.swing.SwingUtilities;

public class EphorSpyProbe {
  public static void main(String[] args) throws Exception {
    String url = null;
    String outArg = ".";
    double timeoutS = 30;
    List<String> channels = new ArrayList<>();
    for (int i = 0; i < args.length; i++) {
      String a = args[i];
      if (a.startsWith("--lcm-url="))
        url = a.substring("--lcm-url=".length());
      else if (a.equals("--out") && i + 1 < args.length)
        outArg = args[++i];
      else if (a.equals("--timeout-s") && i + 1 < args.length)
        timeoutS = Double.parseDouble(args[++i]);
      else if (a.startsWith("-")) {
        System.err.println("EphorSpyProbe: unknown option " + a);
        System.exit(2);
      } else
        channels.add(a);
    }
    if (channels.isEmpty()) {
      System.err.println("EphorSpyProbe: name at least one CHANNEL to check");
      System.exit(2);
    }
    final String out = outArg;
    new File(out).mkdirs();
    Spy spy = new Spy(url);
    long end = System.currentTimeMillis() + (long) (timeoutS * 1000);
    List<String> missing = channels;
    while (System.currentTimeMillis() < end) {
      missing = undecoded(spy, channels);
      if (missing.isEmpty())
        break;
      Thread.sleep(200);
    }
    // One more second of traffic so counts and rates settle in the picture.
    if (missing.isEmpty())
      Thread.sleep(1000);
    ChannelData first = spy.channelMap.get(channels.get(0));
    if (first != null && first.cls != null) {
      SwingUtilities.invokeAndWait(() -> spy.createViewer(first));
      Thread.sleep(1500); // the viewer repaints from the next messages
    }
    try (PrintWriter w = new PrintWriter(new File(out, "channels.txt"))) {
      w.println("channel\ttype\tmessages\tundecodable\thz");
      for (ChannelData cd : spy.channelList)
        w.printf("%s\t%s\t%d\t%d\t%.1f%n", cd.name, cd.cls == null ? "?" : cd.cls.getName(),
            cd.nreceived, cd.nerrors, cd.hz);
    }
    for (String ch : channels) {
      ChannelData cd = spy.channelMap.get(ch);
      if (cd == null || cd.last == null)
        continue;
      try (PrintWriter w = new PrintWriter(new File(out, ch + ".txt"))) {
        dump(w, cd.last, "", 0);
      }
    }
    int n = 0;
    for (Window win : Window.getWindows()) {
      if (!win.isShowing())
        continue;
      final File file = new File(out,
          n == 0       ? "spy.png"
              : n == 1 ? "viewer.png"
                       : "window" + n + ".png");
      SwingUtilities.invokeAndWait(() -> snapshot(win, file));
      n++;
    }
    if (!missing.isEmpty()) {
      System.err.println("EphorSpyProbe: lcm-spy did not decode " + missing + " within " + timeoutS
          + " s (see " + out + "/channels.txt)");
      System.exit(1);
    }
    System.out.println("EphorSpyProbe: lcm-spy decoded " + channels + "; wrote " + out);
    System.exit(0);
  }

  // Channels without decoded messages of one of our types, or with errors.
  static List<String> undecoded(Spy spy, List<String> channels) {
    List<String> missing = new ArrayList<>();
    synchronized (spy) {
      for (String ch : channels) {
        ChannelData cd = spy.channelMap.get(ch);
        boolean ok = cd != null && cd.cls != null && cd.cls.getName().startsWith("ephor.")
            && cd.nreceived > 0 && cd.nerrors == 0 && cd.last != null;
        if (!ok)
          missing.add(ch);
      }
    }
    return missing;
  }

  static void snapshot(Component c, File file) {
    try {
      BufferedImage img = new BufferedImage(
          Math.max(1, c.getWidth()), Math.max(1, c.getHeight()), BufferedImage.TYPE_INT_RGB);
      c.printAll(img.getGraphics());
      ImageIO.write(img, "png", file);
    } catch (Exception e) {
      System.err.println("EphorSpyProbe: cannot write " + file + ": " + e);
    }
  }

  // The public fields of a decoded LCM object, as lcm-spy's viewer lists them.
  static void dump(PrintWriter w, Object o, String prefix, int depth) throws Exception {
    if (depth > 4)
      return;
    for (Field f : o.getClass().getFields()) {
      if (Modifier.isStatic(f.getModifiers()))
        continue;
      Object v = f.get(o);
      String name = prefix + f.getName();
      if (v == null) {
        w.println(name + " = null");
      } else if (v.getClass().isArray()) {
        int len = java.lang.reflect.Array.getLength(v);
        w.println(name + " = [" + len + " elements]");
        for (int i = 0; i < Math.min(len, 8); i++) {
          Object e = java.lang.reflect.Array.get(v, i);
          if (e != null && e.getClass().getName().startsWith("ephor."))
            dump(w, e, name + "[" + i + "].", depth + 1);
          else if (e != null && !(e instanceof Byte))
            w.println(name + "[" + i + "] = " + e);
        }
      } else if (v.getClass().getName().startsWith("ephor.")) {
        dump(w, v, name + ".", depth + 1);
      } else {
        w.println(name + " = " + v);
      }
    }
  }
}
